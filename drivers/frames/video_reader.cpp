// Video files through libavformat (demux), libavcodec (decode) and libswscale (to the
// frame's RGB or grey): damage is detected, never concealed, so that a tool can say where
// a recording stops being trustworthy.
#include "drivers/frames/video_reader.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "drivers/frames/av_error_text.hpp"

namespace ccdlane {

namespace {

// The codecs the issue asks for: dashcams and vehicle cameras record these.
bool supported_codec(AVCodecID id) {
  return id == AV_CODEC_ID_H264 || id == AV_CODEC_ID_HEVC || id == AV_CODEC_ID_MJPEG;
}

bool is_grey(int format) { return format == AV_PIX_FMT_GRAY8; }

}  // namespace

bool is_video_path(std::string_view path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string_view::npos || path.find('/', dot) != std::string_view::npos) return false;
  std::string ext(path.substr(dot + 1));
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == "mp4" || ext == "mkv" || ext == "mov" || ext == "avi" || ext == "m4v" || ext == "webm";
}

// FFmpeg's objects, freed in reverse order of making whatever happens.
struct VideoReader::Codec {
  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  SwsContext* scaler = nullptr;
  int stream = -1;

  Codec() = default;
  Codec(const Codec&) = delete;
  Codec& operator=(const Codec&) = delete;
  ~Codec() {
    sws_freeContext(scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }
};

VideoReader::VideoReader(std::string path) : path_(std::move(path)), av_(std::make_unique<Codec>()) {
  // FFmpeg's own messages would repeat, in its words, what the one line we print says.
  av_log_set_level(AV_LOG_QUIET);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path_, ec)) throw VideoError(path_ + ": no such file");
  Codec& av = *av_;
  if (const int e = avformat_open_input(&av.format, path_.c_str(), nullptr, nullptr); e < 0)
    throw VideoError(path_ + ": not a video, or cut short before its index (" + av_error_text(e) + ")");
  if (const int e = avformat_find_stream_info(av.format, nullptr); e < 0)
    throw VideoError(path_ + ": not a video (" + av_error_text(e) + ")");
  av.stream = av_find_best_stream(av.format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (av.stream < 0) throw VideoError(path_ + ": not a video (no video stream)");
  const AVStream* stream = av.format->streams[av.stream];
  const AVCodecParameters* par = stream->codecpar;
  const char* name = avcodec_get_name(par->codec_id);
  codec_ = name ? name : "unknown";
  if (!supported_codec(par->codec_id))
    throw VideoError(path_ + ": unsupported codec " + codec_ + " (ccdlane reads H.264, H.265 and MJPEG)");
  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  if (!decoder) throw VideoError(path_ + ": unsupported codec " + codec_ + " (no decoder in this FFmpeg)");
  av.decoder = avcodec_alloc_context3(decoder);
  if (!av.decoder || avcodec_parameters_to_context(av.decoder, par) < 0)
    throw std::runtime_error(path_ + ": cannot set up the " + codec_ + " decoder");
  // One thread: the frame-rate figure is per core, and the daemon's other threads need theirs.
  av.decoder->thread_count = 1;
  // Stop at damage instead of concealing it: a concealed frame is a made-up picture.
  av.decoder->err_recognition = AV_EF_EXPLODE | AV_EF_BITSTREAM;
  if (const int e = avcodec_open2(av.decoder, decoder, nullptr); e < 0)
    throw VideoError(path_ + ": cannot decode its " + codec_ + " stream (" + av_error_text(e) + ")");
  width_ = par->width;
  height_ = par->height;
  if (width_ <= 0 || height_ <= 0) throw VideoError(path_ + ": not a video (no frame size)");
  format_ = is_grey(par->format) ? PixelFormat::mono8 : PixelFormat::rgb8;
  tb_num_ = stream->time_base.num;
  tb_den_ = stream->time_base.den;
  if (stream->avg_frame_rate.num > 0 && stream->avg_frame_rate.den > 0) rate_hz_ = av_q2d(stream->avg_frame_rate);
  indexed_frames_ = stream->nb_frames;
  av.packet = av_packet_alloc();
  av.frame = av_frame_alloc();
  if (!av.packet || !av.frame) throw std::runtime_error(path_ + ": out of memory");
}

VideoReader::~VideoReader() = default;

VideoRead VideoReader::fail(const char* what, int av_error) {
  if (av_error != 0) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(av_error, text, sizeof text);
    std::snprintf(problem_.data(), problem_.size(), "%s: frame %llu: %s (%s)", path_.c_str(),
                  static_cast<unsigned long long>(decoded_), what, text);
  } else {
    std::snprintf(problem_.data(), problem_.size(), "%s: frame %llu: %s", path_.c_str(),
                  static_cast<unsigned long long>(decoded_), what);
  }
  stopped_ = VideoRead::damaged;
  return stopped_;
}

// One decoded frame into av.frame: 0, AVERROR_EOF at the end, another negative on damage
// (problem_ set). pts is its presentation time in stream ticks.
int VideoReader::receive(std::int64_t& pts) {
  Codec& av = *av_;
  for (;;) {
    int e = avcodec_receive_frame(av.decoder, av.frame);
    if (e == 0) {
      pts = av.frame->best_effort_timestamp;
      if ((av.frame->flags & AV_FRAME_FLAG_CORRUPT) || av.frame->decode_error_flags) {
        fail("damaged picture data", 0);
        return AVERROR_INVALIDDATA;
      }
      return 0;
    }
    if (e == AVERROR_EOF) return e;
    if (e != AVERROR(EAGAIN)) return fail("damaged picture data", e), e;
    if (draining_) return AVERROR_EOF;
    e = av_read_frame(av.format, av.packet);
    if (e == AVERROR_EOF) {
      draining_ = true;
      avcodec_send_packet(av.decoder, nullptr);  // the decoder gives what it still holds
      continue;
    }
    if (e < 0) return fail("cannot read the file", e), e;
    if (av.packet->stream_index != av.stream) {
      av_packet_unref(av.packet);
      continue;
    }
    const bool corrupt = (av.packet->flags & AV_PKT_FLAG_CORRUPT) != 0;
    e = corrupt ? AVERROR_INVALIDDATA : avcodec_send_packet(av.decoder, av.packet);
    av_packet_unref(av.packet);
    if (corrupt) return fail("cut short (its data end inside this frame)", 0), AVERROR_INVALIDDATA;
    if (e < 0 && e != AVERROR(EAGAIN)) return fail("damaged picture data", e), e;
  }
}

bool VideoReader::convert(const MutableImageView& into) {
  Codec& av = *av_;
  const AVFrame* f = av.frame;
  if (f->width != width_ || f->height != height_) return false;
  const AVPixelFormat out = format_ == PixelFormat::mono8 ? AV_PIX_FMT_GRAY8 : AV_PIX_FMT_RGB24;
  // Same size in and out: only the colour conversion, which swscale does with SIMD. The
  // context is kept while the input format stays (no allocation per frame).
  av.scaler = sws_getCachedContext(av.scaler, f->width, f->height, static_cast<AVPixelFormat>(f->format), width_,
                                   height_, out, SWS_POINT, nullptr, nullptr, nullptr);
  if (!av.scaler) return false;
  std::uint8_t* dst[4] = {into.data, nullptr, nullptr, nullptr};
  const int dst_stride[4] = {static_cast<int>(into.stride_bytes), 0, 0, 0};
  return sws_scale(av.scaler, f->data, f->linesize, 0, f->height, dst, dst_stride) == height_;
}

VideoRead VideoReader::next(const MutableImageView& into, std::int64_t& t_ns) {
  if (stopped_ != VideoRead::frame) return stopped_;
  for (;;) {
    std::int64_t pts = 0;
    const int e = receive(pts);
    if (e == AVERROR_EOF) {
      // A container that lists more frames than it holds was cut short.
      if (indexed_frames_ > 0 && static_cast<std::int64_t>(decoded_) < indexed_frames_) {
        std::snprintf(problem_.data(), problem_.size(), "%s: frame %llu: cut short (its index lists %lld frames)",
                      path_.c_str(), static_cast<unsigned long long>(decoded_),
                      static_cast<long long>(indexed_frames_));
        return stopped_ = VideoRead::damaged;
      }
      return stopped_ = VideoRead::end;
    }
    if (e < 0) return stopped_;
    const std::uint64_t index = decoded_;
    if (pts == AV_NOPTS_VALUE)  // no time at all: one mean period after the last
      pts = have_origin_ ? last_pts_ + (rate_hz_ > 0.0 ? static_cast<std::int64_t>(tb_den_ / (rate_hz_ * tb_num_)) : 1)
                         : 0;
    if (!have_origin_) {
      have_origin_ = true;
      origin_pts_ = pts;
    } else if (pts <= last_pts_) {
      ++non_monotonic_;
      if (first_non_monotonic_ < 0) first_non_monotonic_ = static_cast<std::int64_t>(index);
      ++decoded_;
      continue;
    }
    last_pts_ = pts;
    if (!convert(into)) return fail("its picture size changed", 0);
    ++decoded_;
    t_ns = av_rescale_q(pts - origin_pts_, AVRational{tb_num_, tb_den_}, AVRational{1, 1'000'000'000});
    ++frames_read_;
    return VideoRead::frame;
  }
}

bool VideoReader::rewind() {
  Codec& av = *av_;
  if (av_seek_frame(
          av.format, av.stream,
          av.format->streams[av.stream]->start_time == AV_NOPTS_VALUE ? 0 : av.format->streams[av.stream]->start_time,
          AVSEEK_FLAG_BACKWARD) < 0)
    return false;
  avcodec_flush_buffers(av.decoder);
  frames_read_ = decoded_ = 0;
  have_origin_ = draining_ = false;
  stopped_ = VideoRead::frame;
  problem_[0] = '\0';
  return true;
}

}  // namespace ccdlane
