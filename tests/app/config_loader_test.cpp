// The TOML schema: defaults, every table, and errors that name file, line and key.
#include "app/config_loader.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/as_user.hpp"
#include "tests/support/config_error.hpp"

namespace ccdlane {
namespace {

std::string error_of(const std::string& toml) { return test::config_error_of(toml, "test.toml"); }

TEST(ConfigLoader, EmptyFileGivesTheReferenceCamera) {
  const Config c = parse_config("", "empty.toml");
  EXPECT_EQ(c.camera.Nu, 800);
  EXPECT_EQ(c.camera.cx, 400.5);
  EXPECT_EQ(c.camera.cy, 300.5);
  EXPECT_EQ(c.camera.k_px2, -8.3042e-7);
  EXPECT_EQ(c.H_mm, 1400.0);
  EXPECT_EQ(c.solver.mode, SolverMode::reprojection);
  EXPECT_TRUE(c.solver.free.has(FreeParam::psi));
  EXPECT_FALSE(c.solver.free.has(FreeParam::H));
  EXPECT_EQ(c.lcm.url, "udpm://239.255.76.67:7667?ttl=0");
}

TEST(ConfigLoader, ReadsTheDocumentedExample) {
  const Config c = parse_config(R"(
[camera]
U_mm = 5.12
V_mm = 2.88
Uc_mm = 0.004
Vc_mm = 0.004
Nu = 1280
Nv = 720
f_mm = 4.618
cx = 667.2
k_px2 = -1.91e-7
[mount]
yM_mm = 0
zM_mm = 0
H_mm = 1300
[attitude]
theta_deg = 2
[solver]
mode = "paper"
free = ["psi", "y0"]
pixel_sigma = 1
max_iterations = 20
[prior]
lane_width_mm = [3660.0, 300.0]
phi_deg = [0, 1]
[[lines]]
y0_mm = 1800
[[lines]]
y0_mm = -1800
m = 0.01
[gyro]
sigma_deg = 0.3
device = "emulated"
[source]
kind = "frames"
path = "rec/"
rate_hz = 0
loop = true
[lcm]
prefix = "TEST_"
[realtime]
mlock = true
capture_priority = 50
cpus = [0, 1]
)",
                                "full.toml");
  EXPECT_EQ(c.camera.Nu, 1280);
  EXPECT_EQ(c.camera.cx, 667.2);
  EXPECT_EQ(c.camera.cy, 360.5);  // default (Nv+1)/2
  EXPECT_EQ(c.f_mm, 4.618);
  EXPECT_EQ(c.H_mm, 1300);
  EXPECT_EQ(c.attitude.theta_deg, 2);
  EXPECT_EQ(c.solver.mode, SolverMode::paper);
  EXPECT_TRUE(c.solver.free.has(FreeParam::y0));
  EXPECT_FALSE(c.solver.free.has(FreeParam::theta));
  ASSERT_TRUE(c.prior.lane_width_mm.has_value());
  EXPECT_EQ(c.prior.lane_width_mm->sigma, 300.0);
  EXPECT_FALSE(c.prior.theta_deg.has_value());
  ASSERT_EQ(c.lines.size(), 2u);
  EXPECT_EQ(c.lines[1].m, 0.01);
  EXPECT_EQ(c.gyro.device, "emulated");
  EXPECT_EQ(c.source.kind, SourceKind::frames);
  EXPECT_TRUE(c.source.loop);
  EXPECT_EQ(c.lcm.prefix, "TEST_");
  EXPECT_EQ(c.realtime.cpus, (std::vector<int>{0, 1}));
  EXPECT_NEAR(c.nominal_pose().attitude.theta, deg_to_rad(2), 1e-15);
}

TEST(ConfigLoader, IntegersAreAcceptedWhereNumbersAre) {
  EXPECT_EQ(parse_config("[mount]\nH_mm = 1250\n", "t.toml").H_mm, 1250.0);
}

TEST(ConfigLoader, UnknownKeyNamesFileLineAndKey) {
  EXPECT_EQ(error_of("[camera]\nNu = 800\nfocal = 5\n"), "test.toml:3: camera.focal: unknown key");
  EXPECT_EQ(error_of("\n[camra]\n"), "test.toml:2: camra: unknown key");
  EXPECT_EQ(error_of("[[lines]]\ny0_mm = 1\n[[lines]]\ny0 = 2\n"), "test.toml:4: lines[1].y0: unknown key");
}

TEST(ConfigLoader, WrongTypes) {
  EXPECT_EQ(error_of("[camera]\nNu = 800.5\n"), "test.toml:2: camera.Nu: must be an integer, got a number");
  EXPECT_EQ(error_of("[mount]\nH_mm = \"high\"\n"), "test.toml:2: mount.H_mm: must be a number, got a string");
  EXPECT_EQ(error_of("camera = 3\n"), "test.toml:1: camera: must be a table ([camera])");
  EXPECT_EQ(error_of("[prior]\nphi_deg = 0.5\n"), "test.toml:2: prior.phi_deg: must be [mean, sigma], two numbers");
}

// Values that passed --check-config but could not work: sigmas of 1e+-300 and a prior of
// 1e300 made every frame rank_deficient, rate_hz = 1e-300 ran flat out.
TEST(ConfigLoader, SigmasPriorsAndRatesOutsidePhysicalRanges) {
  EXPECT_EQ(error_of("[prior]\nH_mm = [1e300, 20]\n"), "test.toml:2: prior.H_mm: mean must be 1 .. 20000, got 1e+300");
  EXPECT_EQ(error_of("[prior]\nphi_deg = [0, 1e-300]\n"),
            "test.toml:2: prior.phi_deg: sigma must be 0.001 .. 90, got 1e-300");
  EXPECT_EQ(error_of("[prior]\nlane_width_mm = [3600, 1e300]\n"),
            "test.toml:2: prior.lane_width_mm: sigma must be 0.01 .. 10000, got 1e+300");
  EXPECT_EQ(error_of("[solver]\npixel_sigma = 1e300\n"),
            "test.toml:2: solver.pixel_sigma: must be 0.001 .. 1000 pixels");
  EXPECT_EQ(error_of("[solver]\npixel_sigma = 1e-300\n"),
            "test.toml:2: solver.pixel_sigma: must be 0.001 .. 1000 pixels");
  EXPECT_EQ(error_of("[gyro]\nsigma_deg = 1e-300\n"), "test.toml:2: gyro.sigma_deg: must be 0.001 .. 90 degrees");
  EXPECT_EQ(error_of("[source]\nrate_hz = 1e-300\n"),
            "test.toml:2: source.rate_hz: must be 0 (as recorded) or 0.1 .. 1000");
  EXPECT_EQ(error_of("[prior]\nH_mm = [1400, 20]\nphi_deg = [0, 1]\n[source]\nrate_hz = 0\n"), "(no error)");
}

TEST(ConfigLoader, ImpossibleValues) {
  EXPECT_EQ(error_of("[camera]\nU_mm = -6.4\n"), "test.toml:2: camera.U_mm: must be > 0, got -6.4");
  EXPECT_EQ(error_of("[camera]\nNu = 1\n"), "test.toml:2: camera.Nu: must be at least 2, got 1");
  EXPECT_EQ(error_of("[camera]\nUc_mm = 7\n"),
            "test.toml:2: camera.Uc_mm: a cell cannot be as wide as the chip (U_mm = 6.4)");
  EXPECT_EQ(error_of("[camera]\nNu = 8000\n"),
            "test.toml:2: camera.Nu: Nu cells of Uc_mm do not fit on a chip U_mm wide");
  // A data sheet's cell size rounded to four figures fits; one a cell too many does not.
  EXPECT_EQ(
      error_of(
          "[camera]\nU_mm = 5.12\nV_mm = 2.88\nUc_mm = 0.002667\nVc_mm = 0.002667\nNu = 1920\nNv = 1080\nk_px2 = 0\n"),
      "(no error)");
  EXPECT_EQ(
      error_of(
          "[camera]\nU_mm = 5.12\nV_mm = 2.88\nUc_mm = 0.002667\nVc_mm = 0.002667\nNu = 1922\nNv = 1080\nk_px2 = 0\n"),
      "test.toml:6: camera.Nu: Nu cells of Uc_mm do not fit on a chip U_mm wide");
  EXPECT_EQ(error_of("[mount]\nH_mm = 0\n"),
            "test.toml:2: mount.H_mm: the camera must be above the road (H_mm > 0), got 0");
  EXPECT_EQ(error_of("[solver]\nmode = \"fast\"\n"),
            "test.toml:2: solver.mode: must be \"reprojection\" or \"paper\", got \"fast\"");
  EXPECT_EQ(error_of("[solver]\nfree = [\"psi\", \"roll\"]\n"),
            "test.toml:2: solver.free: unknown parameter \"roll\"; expected any of psi theta phi H f y0 m c");
  EXPECT_EQ(error_of("[prior]\nH_mm = [1400, 0]\n"), "test.toml:2: prior.H_mm: needs a finite mean and a sigma > 0");
  EXPECT_EQ(error_of("[camera]\ncx = 900\n"),
            "test.toml:2: camera.cx: principal point must lie on the chip (0.5 .. Nu+0.5)");
  EXPECT_EQ(error_of("[camera]\nk_px2 = 1e-5\n"),
            "test.toml:2: camera.k_px2: distortion this strong makes the image corners ambiguous (|k_px2| * r_corner^2 "
            "must be < 1)");
  EXPECT_EQ(error_of("[source]\nkind = \"frames\"\n"),
            "test.toml:1: source.path: a \"frames\" source needs path = the frame directory");
  EXPECT_EQ(error_of("[source]\nkind = \"video\"\n"),
            "test.toml:1: source.path: a \"video\" source needs path = the video file");
  EXPECT_EQ(error_of("[realtime]\ncapture_priority = 120\n"),
            "test.toml:2: realtime.capture_priority: must be a SCHED_FIFO priority 0..99");
}

TEST(ConfigLoader, EmptyFreeSetIsRejected) {
  // Nothing free leaves the solver nothing to solve: refused here, where the file and the
  // line can still be named, rather than on the first frame.
  EXPECT_EQ(error_of("[solver]\nmode = \"paper\"\nfree = []\n"),
            "test.toml:3: solver.free: must name at least one parameter (psi theta phi H f y0 m c)");
}

TEST(ConfigLoader, LineModelStraightOrCurved) {
  // Curved by default, as default_config() has it; freeing c (a curvature per line)
  // means the straight model's per-line c, as it did before curved was the default.
  EXPECT_EQ(parse_config("", "empty.toml").solver.line_model, LineModel::shared_curvature);
  EXPECT_EQ(default_config().solver.line_model, LineModel::shared_curvature);
  EXPECT_EQ(parse_config("[solver]\nfree = [\"psi\", \"y0\", \"c\"]\n", "f.toml").solver.line_model,
            LineModel::per_line);
  EXPECT_EQ(parse_config("[solver]\nline_model = \"straight\"\n", "f.toml").solver.line_model, LineModel::per_line);
  EXPECT_EQ(parse_config("[solver]\nline_model = \"curved\"\n", "f.toml").solver.line_model,
            LineModel::shared_curvature);
  EXPECT_EQ(error_of("[solver]\nline_model = \"clothoid\"\n"),
            "test.toml:2: solver.line_model: must be \"straight\" or \"curved\", got \"clothoid\"");
  EXPECT_EQ(error_of("[solver]\nfree = [\"psi\", \"y0\", \"c\"]\nline_model = \"curved\"\n"),
            "test.toml:3: solver.line_model: \"curved\" solves one curvature shared by all lines: leave c out of "
            "free (c frees one per line)");
}

TEST(ConfigLoader, SourcePixelFormatAutoGreyOrColour) {
  EXPECT_EQ(parse_config("", "empty.toml").source.pixel_format, SourcePixels::automatic);
  EXPECT_EQ(parse_config("[source]\npixel_format = \"grey\"\n", "f.toml").source.pixel_format, SourcePixels::grey);
  EXPECT_EQ(parse_config("[source]\npixel_format = \"colour\"\n", "f.toml").source.pixel_format, SourcePixels::colour);
  EXPECT_EQ(parse_config("", "empty.toml").source.device_format, "");
  EXPECT_EQ(parse_config("[source]\ndevice_format = \"BayerGR8\"\n", "f.toml").source.device_format, "BayerGR8");
  EXPECT_EQ(error_of("[source]\npixel_format = \"bayer\"\n"),
            "test.toml:2: source.pixel_format: must be \"auto\", \"grey\" or \"colour\", got \"bayer\"");
}

TEST(ConfigLoader, SyntaxErrorsNameTheLine) {
  const std::string e = error_of("[camera]\nNu = = 3\n");
  EXPECT_EQ(e.rfind("test.toml:2: ", 0), 0u) << e;
}

TEST(ConfigLoader, MissingFileIsAConfigError) {
  EXPECT_THROW(load_config_file("/nonexistent/ccdlane.toml"), ConfigError);
}

std::string load_error(const std::string& path) {
  try {
    load_config_file(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

// [source] path was once taken relative to the working directory (systemd's is /).
TEST(ConfigLoader, ARelativeSourcePathIsTheConfigurationFilesNeighbour) {
  const std::string dir = testing::TempDir() + "/config-" + std::to_string(::getpid());
  ::mkdir(dir.c_str(), 0700);
  const std::string path = dir + "/ccdlane.toml";
  std::ofstream(path) << "[source]\nkind = \"frames\"\npath = \"rec\"\n";
  EXPECT_EQ(load_config_file(path).source.path, dir + "/rec");
  std::ofstream(path) << "[source]\nkind = \"frames\"\npath = \"/data/rec\"\n";
  EXPECT_EQ(load_config_file(path).source.path, "/data/rec");
  ::unlink(path.c_str());
  ::rmdir(dir.c_str());
}

TEST(ConfigLoader, ADirectoryIsNoConfiguration) {
  EXPECT_EQ(load_error("/etc"), "/etc: is a directory, not a configuration file");
}

TEST(ConfigLoader, AnEndlessFileIsReadOnlyUpToOneMegabyte) {
  EXPECT_EQ(load_error("/dev/zero"), "/dev/zero: larger than 1 MB: not a configuration file");
}

TEST(ConfigLoader, AFileThatCannotBeOpenedSaysWhy) {
  EXPECT_EQ(load_error("/nonexistent/ccdlane.toml"),
            "/nonexistent/ccdlane.toml: cannot read the configuration file: No such file or directory");
  char dir[] = "/tmp/ccdlane-config-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  ::chmod(dir, 0755);  // a user other than its owner may look inside
  const std::string path = std::string(dir) + "/locked.toml";
  { std::ofstream(path) << "[camera]\n"; }
  ::chmod(path.c_str(), 0);
  const std::string expected = path + ": cannot read the configuration file: Permission denied";
  if (::geteuid() == 0) {
    // Root reads any file whatever its permissions (CI runs as root): as nobody.
    const test::ChildRun nobody = test::run_as_user(
        test::kNobody, [] { return true; },
        [&path](int fd) {
          const std::string text = load_error(path);
          return ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) ? 0 : 12;
        });
    EXPECT_TRUE(nobody.exited_with(0)) << nobody.status;
    EXPECT_EQ(nobody.out, expected) << "as nobody";
  } else {
    EXPECT_EQ(load_error(path), expected);
  }
  ::unlink(path.c_str());
  ::rmdir(dir);
}

TEST(ConfigLoader, PicturesTooLargeToAllocateAreRefused) {
  EXPECT_EQ(error_of("[camera]\nNu = 100000\nNv = 100000\nUc_mm = 0.00001\nVc_mm = 0.00001\n"),
            "test.toml:2: camera.Nu: must be at most 8192 pixels, got 100000");
  EXPECT_EQ(error_of("[camera]\nNv = 8193\nVc_mm = 0.0001\n"),
            "test.toml:2: camera.Nv: must be at most 8192 pixels, got 8193");
}

TEST(ConfigLoader, DaemonTableAndRealtimeExtras) {
  const Config d = parse_config("", "empty.toml");
  EXPECT_EQ(d.daemon.queue_depth, 4);
  EXPECT_EQ(d.daemon.stall_timeout_s, 2.0);
  EXPECT_EQ(d.realtime.gyro_priority, 0);
  EXPECT_EQ(d.lcm.prefix, "CCDLANE_");

  const Config c = parse_config(
      "[daemon]\nqueue_depth = 8\nstall_timeout_s = 0.5\n"
      "[realtime]\ngyro_priority = 40\n[lcm]\nprefix = \"car-7/front.\"\n",
      "d.toml");
  EXPECT_EQ(c.daemon.queue_depth, 8);
  EXPECT_EQ(c.daemon.stall_timeout_s, 0.5);
  EXPECT_EQ(c.realtime.gyro_priority, 40);
  EXPECT_EQ(c.lcm.prefix, "car-7/front.");

  EXPECT_EQ(error_of("[daemon]\nqueue_depth = 0\n"),
            "test.toml:2: daemon.queue_depth: must be between 1 and 62 frames");
  EXPECT_EQ(error_of("[daemon]\nqueue_depth = 63\n"),
            "test.toml:2: daemon.queue_depth: must be between 1 and 62 frames");
  EXPECT_EQ(error_of("[daemon]\nstall_timeout_s = 0\n"),
            "test.toml:2: daemon.stall_timeout_s: must be between 0.1 and 3600 seconds");
  EXPECT_EQ(error_of("[daemon]\npool = 3\n"), "test.toml:2: daemon.pool: unknown key");
  EXPECT_EQ(error_of("[realtime]\ngyro_priority = -1\n"),
            "test.toml:2: realtime.gyro_priority: must be a SCHED_FIFO priority 0..99");
  EXPECT_EQ(d.lcm.instance, "") << "default: the daemon names itself host:pid";
  EXPECT_EQ(parse_config("[lcm]\ninstance = \"car-7/front:cam@2\"\n", "i.toml").lcm.instance, "car-7/front:cam@2");
  EXPECT_EQ(parse_config("[lcm]\ninstance = \"" + std::string(64, 'i') + "\"\n", "i.toml").lcm.instance.size(), 64u);
  EXPECT_EQ(error_of("[lcm]\ninstance = \"" + std::string(65, 'i') + "\"\n"),
            "test.toml:2: lcm.instance: must be at most 64 characters");
  for (const char* bad : {"car 7", "car\\\"7", "car\\n7", "caf\u00e9", "a,b"})
    EXPECT_EQ(error_of(std::string("[lcm]\ninstance = \"") + bad + "\"\n"),
              "test.toml:2: lcm.instance: may hold only letters, digits and _ - . : / @ (\"\" = host:pid)")
        << bad;
  EXPECT_EQ(error_of("[lcm]\nprefix = \"CCD LANE\"\n"),
            "test.toml:2: lcm.prefix: may hold only letters, digits and _ - . /");
  EXPECT_EQ(error_of("[lcm]\nprefix = \"" + std::string(49, 'P') + "\"\n"),
            "test.toml:2: lcm.prefix: must be at most 48 characters");
  EXPECT_EQ(error_of("[lcm]\nurl = \"\"\n"),
            "test.toml:2: lcm.url: must name an LCM bus (udpm://, memq:// or file://), e.g. "
            "\"udpm://239.255.76.67:7667?ttl=0\"");
  EXPECT_EQ(error_of("[lcm]\nurl = \"udp://239.255.76.67:7667\"\n"),
            "test.toml:2: lcm.url: must name an LCM bus (udpm://, memq:// or file://), e.g. "
            "\"udpm://239.255.76.67:7667?ttl=0\"");
  EXPECT_EQ(parse_config("[lcm]\nurl = \"memq://\"\n", "m.toml").lcm.url, "memq://");
  // LCM's tcpq client aborted ccdlaned and monitor 2 s after start without its server.
  EXPECT_EQ(error_of("[lcm]\nurl = \"tcpq://192.0.2.1:7700\"\n"),
            "test.toml:2: lcm.url: tcpq:// is not supported (LCM's tcpq client aborts the process when its server is "
            "unreachable); use udpm://, memq:// or file://");
}

TEST(ConfigLoader, PublishFramesIsOffUnlessAsked) {
  EXPECT_FALSE(parse_config("", "empty.toml").lcm.publish_frames);
  EXPECT_TRUE(parse_config("[lcm]\npublish_frames = true\n", "f.toml").lcm.publish_frames);
  EXPECT_EQ(error_of("[lcm]\npublish_frames = 1\n"),
            "test.toml:2: lcm.publish_frames: must be true or false, got an integer");
}

TEST(ConfigLoader, VehicleAndLdwTables) {
  const Config d = parse_config("", "empty.toml");
  EXPECT_EQ(d.vehicle, ldw::VehicleConfig{});
  EXPECT_EQ(d.ldw, ldw::LdwConfig{});
  EXPECT_TRUE(d.estimator_options().ldw.filter.track_roll) << "no gyro: the filter tracks roll";

  const Config c = parse_config(
      "[vehicle]\nspeed_kmh = 90\nwidth_mm = 1900\nfront_axle_behind_camera_mm = -1200\n"
      "camera_left_of_centre_mm = -100\n[ldw]\nmin_speed_kmh = 55\nindicator_hold_s = 3\n"
      "coast_s = 0.5\n[gyro]\ndevice = \"emulated\"\n",
      "v.toml");
  EXPECT_EQ(c.vehicle.speed_kmh, 90.0);
  EXPECT_EQ(c.vehicle.width_mm, 1900.0);
  EXPECT_EQ(c.vehicle.front_axle_behind_camera_mm, -1200.0);
  EXPECT_EQ(c.vehicle.camera_left_of_centre_mm, -100.0);
  EXPECT_EQ(c.ldw.warning.min_speed_kmh, 55.0);
  EXPECT_EQ(c.ldw.warning.indicator_hold_s, 3.0);
  EXPECT_EQ(c.ldw.filter.coast_s, 0.5);
  const LaneEstimatorOptions o = c.estimator_options();
  EXPECT_EQ(o.ldw.vehicle, c.vehicle) << "[vehicle] reaches the estimator";
  EXPECT_EQ(o.ldw.warning.min_speed_kmh, 55.0);
  EXPECT_FALSE(o.ldw.filter.track_roll) << "the gyro measures roll";

  EXPECT_EQ(error_of("[vehicle]\nwheelbase_mm = 2700\n"), "test.toml:2: vehicle.wheelbase_mm: unknown key");
  EXPECT_EQ(error_of("[vehicle]\nwidth_mm = 500\n"),
            "test.toml:2: vehicle.width_mm: must be 1000..3000 (a road vehicle's track)");
  EXPECT_EQ(error_of("[vehicle]\ncamera_left_of_centre_mm = 1000\n"),
            "test.toml:2: vehicle.camera_left_of_centre_mm: must put the camera within the vehicle's width "
            "(+-width_mm / 2)");
  EXPECT_EQ(error_of("[ldw]\nlatest_warning_mm = 300\n"),
            "test.toml:2: ldw.latest_warning_mm: must be beyond the line: -2000 .. < 0");
  EXPECT_EQ(error_of("[ldw]\ngate_probability = 1\n"), "test.toml:2: ldw.gate_probability: must be within (0.5, 1)");
  EXPECT_EQ(error_of("[ldw]\nconfirm_updates = 2.5\n"),
            "test.toml:2: ldw.confirm_updates: must be an integer, got a number");
}

TEST(ConfigLoader, CalibrationTable) {
  const Config d = parse_config("", "empty.toml");
  EXPECT_EQ(d.calibration, CalibrationConfig{});
  EXPECT_FALSE(d.calibration.online);

  const Config c = parse_config(
      "[attitude]\npsi_deg = 0.5\ntheta_deg = 4\n[calibration]\nonline = true\nmin_speed_kmh = 40\n"
      "min_radius_m = 2000\nmax_correction_deg = 2\nmax_change_deg_per_min = 1\nframes_needed = 600\n"
      "state_file = \"/var/lib/x/m.toml\"\nsave_period_s = 30\n",
      "k.toml");
  EXPECT_TRUE(c.calibration.online);
  EXPECT_EQ(c.calibration.state_file, "/var/lib/x/m.toml");
  EXPECT_EQ(c.calibration.save_period_s, 30.0);
  const calibration::OnlineMountOptions o = c.online_mount_options();
  EXPECT_EQ(o.configured_psi_deg, 0.5) << "the configured mount is the centre";
  EXPECT_EQ(o.configured_theta_deg, 4.0);
  EXPECT_EQ(o.min_speed_kmh, 40.0);
  EXPECT_EQ(o.max_curvature_per_m, 1.0 / 2000.0);
  EXPECT_EQ(o.max_correction_deg, 2.0);
  EXPECT_EQ(o.max_change_deg_per_min, 1.0);
  EXPECT_EQ(o.frames_needed, 600);

  EXPECT_EQ(error_of("[calibration]\nonline = 1\n"),
            "test.toml:2: calibration.online: must be true or false, got an integer");
  EXPECT_EQ(error_of("[calibration]\nmax_correction_deg = 0\n"),
            "test.toml:2: calibration.max_correction_deg: must be > 0 and <= 10");
  EXPECT_EQ(error_of("[calibration]\nframes_needed = 10\n"),
            "test.toml:2: calibration.frames_needed: must be 30..1000000");
  EXPECT_EQ(error_of("[calibration]\nstate_file = \"m.toml\"\n"),
            "test.toml:2: calibration.state_file: must be an absolute path (or left out: "
            "$STATE_DIRECTORY/mount-refinement.toml)");
  EXPECT_EQ(error_of("[calibration]\nyaw = 1\n"), "test.toml:2: calibration.yaw: unknown key");
}

TEST(ConfigLoader, ConfigKeysListsWhatTheLoaderAccepts) {
  const std::vector<std::string> keys = config_keys();
  for (const char* k : {"camera.Nu",
                        "camera.cx",
                        "mount.H_mm",
                        "solver.free",
                        "prior.lane_width_mm",
                        "gyro.device",
                        "source.kind",
                        "lcm.publish_frames",
                        "realtime.cpus",
                        "daemon.queue_depth",
                        "synth.seed",
                        "detection.departure_mm",
                        "vehicle.speed_kmh",
                        "vehicle.width_mm",
                        "vehicle.front_axle_behind_camera_mm",
                        "vehicle.camera_left_of_centre_mm",
                        "ldw.min_speed_kmh",
                        "ldw.indicator_hold_s",
                        "ldw.coast_s",
                        "lines.y0_mm",
                        "lines.c_per_mm"})
    EXPECT_NE(std::find(keys.begin(), keys.end(), k), keys.end()) << k;
  std::vector<std::string> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a key listed twice";
  // Every key listed is one the loader takes: given a value of the wrong type, it is
  // refused as that key, not as an unknown one.
  for (const std::string& key : keys) {
    const auto dot = key.find('.');
    const std::string table = key.substr(0, dot), name = key.substr(dot + 1);
    const std::string text = (table == "lines" ? "[[lines]]\n" : "[" + table + "]\n") + name + " = {}\n";
    const std::string e = error_of(text);
    const std::string expected_key = table == "lines" ? "lines[0]." + name : key;
    EXPECT_NE(e.find(expected_key + ": "), std::string::npos) << e;
    EXPECT_EQ(e.find("unknown key"), std::string::npos) << e;
  }
}

}  // namespace
// Every named choice reads through one helper: four or more options are listed as "one of",
// a value of the wrong type is a type error, not an unknown name.
TEST(ConfigLoader, SourceKindIsOneOfFiveAndATypeErrorIsSaidAsSuch) {
  EXPECT_EQ(parse_config("[source]\nkind = \"frames\"\npath = \"/tmp\"\n", "f.toml").source.kind, SourceKind::frames);
  EXPECT_EQ(parse_config("[source]\nkind = \"video\"\npath = \"d.mp4\"\n", "f.toml").source.kind, SourceKind::video);
  EXPECT_EQ(
      error_of("[source]\nkind = \"usb\"\n"),
      "test.toml:2: source.kind: must be one of \"synth\", \"frames\", \"v4l2\", \"aravis\", \"video\", got \"usb\"");
  EXPECT_EQ(error_of("[source]\nkind = 3\n"), "test.toml:2: source.kind: must be a string, got an integer");
}

}  // namespace ccdlane
