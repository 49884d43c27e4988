// Video encoding through libswscale (to the encoder's YUV), libavcodec and libavformat,
// into a temporary file renamed into place when it is whole.
#include "drivers/frames/video_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "drivers/frames/av_error_text.hpp"

namespace ccdlane {

namespace {

AVPixelFormat av_format_of(PixelFormat f) {
  switch (f) {
    case PixelFormat::mono8: return AV_PIX_FMT_GRAY8;
    case PixelFormat::rgb8: return AV_PIX_FMT_RGB24;
    case PixelFormat::bgr8: return AV_PIX_FMT_BGR24;
    case PixelFormat::mono16: break;
  }
  return AV_PIX_FMT_NONE;
}

}  // namespace

struct VideoWriter::Codec {
  AVFormatContext* format = nullptr;
  AVCodecContext* encoder = nullptr;
  AVStream* stream = nullptr;  // owned by format
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scaler = nullptr;

  Codec() = default;
  Codec(const Codec&) = delete;
  Codec& operator=(const Codec&) = delete;
  ~Codec() {
    sws_freeContext(scaler);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&encoder);
    if (format) avio_closep(&format->pb);
    avformat_free_context(format);
  }
};

namespace {

// Encoder settings: fast presets (an overlay is written at replay speed), lossless on request.
AVDictionary* encoder_options(const VideoWriterOptions& o, AVCodecContext* encoder) {
  AVDictionary* d = nullptr;
  if (o.encoder == "libx264") {
    // Lossless test recordings are small; annotated replays must keep pace with replay.
    av_dict_set(&d, "preset", o.lossless ? "veryfast" : "superfast", 0);
    if (o.lossless) av_dict_set(&d, "qp", "0", 0);
  } else if (o.encoder == "libx265") {
    av_dict_set(&d, "preset", "ultrafast", 0);
    av_dict_set(&d, "x265-params", o.lossless ? "log-level=none:lossless=1" : "log-level=none", 0);
  } else if (o.encoder == "mjpeg") {
    encoder->flags |= AV_CODEC_FLAG_QSCALE;  // a fixed, high quality
    encoder->global_quality = FF_QP2LAMBDA * 2;
  }
  return d;
}

}  // namespace

VideoWriter::VideoWriter(std::string path, VideoWriterOptions options)
    : path_(std::move(path)),
      part_path_(path_ + ".part"),
      options_(std::move(options)),
      av_(std::make_unique<Codec>()) {
  av_log_set_level(AV_LOG_QUIET);
  Codec& av = *av_;
  const auto fail = [this](const std::string& what) { return std::runtime_error(path_ + ": " + what); };
  // The container from the name asked for (the temporary name has another extension).
  const AVOutputFormat* container = av_guess_format(nullptr, path_.c_str(), nullptr);
  if (!container) throw fail("no video container for this file name (use .mp4, .mkv, .mov or .avi)");
  if (avformat_alloc_output_context2(&av.format, container, nullptr, part_path_.c_str()) < 0 || !av.format)
    throw fail("cannot set up the container");
  const AVCodec* codec = avcodec_find_encoder_by_name(options_.encoder.c_str());
  if (!codec) throw fail("no encoder " + options_.encoder + " in this FFmpeg");
  av.encoder = avcodec_alloc_context3(codec);
  if (!av.encoder) throw fail("out of memory");
  av.encoder->width = options_.width;
  av.encoder->height = options_.height;
  av.encoder->time_base = AVRational{options_.time_base_num, options_.time_base_den};
  av.encoder->pix_fmt = codec->pix_fmts ? codec->pix_fmts[0] : AV_PIX_FMT_YUV420P;
  // The encoder's own threads (x264 pipelines frames): an overlay is written while the
  // replay waits for nothing else.
  av.encoder->thread_count = 0;
  last_interval_ = std::max<std::int64_t>(1, av_rescale_q(1, AVRational{1, 30}, av.encoder->time_base));
  if (container->flags & AVFMT_GLOBALHEADER) av.encoder->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  AVDictionary* opts = encoder_options(options_, av.encoder);
  const int opened = avcodec_open2(av.encoder, codec, &opts);
  av_dict_free(&opts);
  if (opened < 0) throw fail("cannot open the " + options_.encoder + " encoder (" + av_error_text(opened) + ")");
  av.stream = avformat_new_stream(av.format, nullptr);
  if (!av.stream || avcodec_parameters_from_context(av.stream->codecpar, av.encoder) < 0)
    throw fail("cannot add the video stream");
  av.stream->time_base = av.encoder->time_base;
  av.frame = av_frame_alloc();
  av.packet = av_packet_alloc();
  if (!av.frame || !av.packet) throw fail("out of memory");
  av.frame->format = av.encoder->pix_fmt;
  av.frame->width = options_.width;
  av.frame->height = options_.height;
  if (av_frame_get_buffer(av.frame, 0) < 0) throw fail("out of memory");
  if (const int e = avio_open(&av.format->pb, part_path_.c_str(), AVIO_FLAG_WRITE); e < 0)
    throw std::runtime_error(part_path_ + ": cannot create (" + av_error_text(e) + ")");
  // MP4 and MOV with their index first: a copy cut short still plays up to the cut.
  AVDictionary* mux = nullptr;
  av_dict_set(&mux, "movflags", "+faststart", 0);
  const int header = avformat_write_header(av.format, &mux);
  av_dict_free(&mux);
  if (header < 0) {
    std::filesystem::remove(part_path_);
    throw fail("cannot write the header (" + av_error_text(header) + ")");
  }
}

VideoWriter::~VideoWriter() {
  if (finished_) return;
  av_.reset();  // closes the file first
  std::error_code ec;
  std::filesystem::remove(part_path_, ec);
}

void VideoWriter::drain(bool flushing) {
  Codec& av = *av_;
  int e = 0;
  while ((e = avcodec_receive_packet(av.encoder, av.packet)) == 0) {
    // The last frame's duration is what a container keeps it on screen for (MP4's edit
    // list drops a frame of none): the latest interval between frames.
    if (av.packet->duration <= 0) av.packet->duration = last_interval_;
    av_packet_rescale_ts(av.packet, av.encoder->time_base, av.stream->time_base);
    av.packet->stream_index = av.stream->index;
    e = av_interleaved_write_frame(av.format, av.packet);  // takes the packet's data
    if (e < 0) throw std::runtime_error(part_path_ + ": cannot write (" + av_error_text(e) + ")");
  }
  if (e != AVERROR(EAGAIN) && !(flushing && e == AVERROR_EOF))
    throw std::runtime_error(path_ + ": encoding failed (" + av_error_text(e) + ")");
}

void VideoWriter::write(const ImageView& frame, std::int64_t t_ns) {
  Codec& av = *av_;
  if (frame.width != options_.width || frame.height != options_.height)
    throw std::runtime_error(path_ + ": a frame of " + std::to_string(frame.width) + "x" +
                             std::to_string(frame.height) + " in a video of " + std::to_string(options_.width) + "x" +
                             std::to_string(options_.height));
  const AVPixelFormat in = av_format_of(frame.format);
  if (in == AV_PIX_FMT_NONE) throw std::runtime_error(path_ + ": 16-bit frames cannot be encoded");
  const std::int64_t pts = av_rescale_q(t_ns, AVRational{1, 1'000'000'000}, av.encoder->time_base);
  if (pts <= last_pts_)
    throw std::runtime_error(path_ + ": frame " + std::to_string(frames_) + " at " + std::to_string(t_ns) +
                             " ns does not come after the previous one in the time base");
  av.scaler = sws_getCachedContext(av.scaler, frame.width, frame.height, in, options_.width, options_.height,
                                   av.encoder->pix_fmt, SWS_BILINEAR | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
  if (!av.scaler || av_frame_make_writable(av.frame) < 0) throw std::runtime_error(path_ + ": out of memory");
  const std::uint8_t* src[4] = {frame.data, nullptr, nullptr, nullptr};
  const int src_stride[4] = {static_cast<int>(frame.stride_bytes), 0, 0, 0};
  sws_scale(av.scaler, src, src_stride, 0, frame.height, av.frame->data, av.frame->linesize);
  av.frame->pts = pts;
  if (last_pts_ >= 0) last_interval_ = pts - last_pts_;
  last_pts_ = pts;
  if (const int e = avcodec_send_frame(av.encoder, av.frame); e < 0)
    throw std::runtime_error(path_ + ": encoding failed (" + av_error_text(e) + ")");
  drain(false);
  ++frames_;
}

void VideoWriter::finish() {
  Codec& av = *av_;
  avcodec_send_frame(av.encoder, nullptr);
  drain(true);
  if (const int e = av_write_trailer(av.format); e < 0)
    throw std::runtime_error(part_path_ + ": cannot finish (" + av_error_text(e) + ")");
  if (const int e = avio_closep(&av.format->pb); e < 0)
    throw std::runtime_error(part_path_ + ": cannot close (" + av_error_text(e) + ")");
  std::filesystem::rename(part_path_, path_);
  finished_ = true;
}

}  // namespace ccdlane
