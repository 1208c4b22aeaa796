#include "vision_commands.h"

#include "cli.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/image/read_image.h"
#include "mapnav/vision/calibrate.h"

namespace mapnav::cli {

namespace {

void requireOutput(const std::string& output, const char* option) {
  if (output.empty()) throw UsageError(std::string("missing ") + option + ": where to write the result");
}

}  // namespace

int runRectify(const RectifyConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    requireOutput(config.output, "--output");
    config.options.validate();
    const std::unique_ptr<Camera> camera = loadCamera(config.camera);
    const Image frame = readImage(config.image);
    if (frame.width != camera->width() || frame.height != camera->height()) {
      throw InvalidInput(config.image + ": the image is " + std::to_string(frame.width) + "x" +
                         std::to_string(frame.height) + ", the camera (" + config.camera + ") expects " +
                         std::to_string(camera->width()) + "x" + std::to_string(camera->height()));
    }
    if (config.undistort) {
      writePng(undistortFrame(*camera, frame), config.output);
      out << "wrote " << config.output << ": " << frame.width << "x" << frame.height
          << " px, undistorted (the camera's ideal pin-hole: straight lines are straight)\n";
      return 0;
    }
    const Rectifier rectifier(*camera, config.options);
    const Image rectified = rectifier.apply(frame);
    writePng(rectified, config.output);
    const RectifyOptions& o = config.options;
    out << "wrote " << config.output << ": " << rectified.width << "x" << rectified.height << " px, "
        << o.metres_per_pixel << " m/px, x " << o.x_max_m << " (top) to " << o.x_min_m << " m (bottom), y "
        << o.y_max_m << " (left) to " << o.y_min_m << " m (right); " << std::fixed << std::setprecision(1)
        << 100.0 * rectifier.coverage() << "% of the grid in view\n";
    return 0;
  });
}

int runCalibrateChessboard(const CalibrateChessboardConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    requireOutput(config.output, "--output");
    if (config.images.empty()) throw UsageError("no images given");
    if (config.size_tolerance_px < 0) {
      throw InvalidInput("--size-tolerance " + std::to_string(config.size_tolerance_px) + ": must be >= 0");
    }
    // In the order of their file names, so that the result does not depend on the order given.
    std::vector<std::string> files = config.images;
    std::sort(files.begin(), files.end());
    std::vector<Image> images;
    for (const std::string& file : files) images.push_back(readImage(file));
    const ChessboardResult result =
        calibrateChessboard(images, config.cols, config.rows, config.square_m, files, config.size_tolerance_px);

    if (!config.corners_dir.empty()) {
      std::filesystem::create_directories(config.corners_dir);
      for (std::size_t i = 0; i < images.size(); ++i) {
        const auto corners = findChessboard(images[i], config.cols, config.rows);
        const Image drawn =
            drawChessboardCorners(images[i], config.cols, config.rows, corners.value_or(std::vector<Vec2>{}), corners.has_value());
        const std::filesystem::path name =
            std::filesystem::path(config.corners_dir) /
            (std::filesystem::path(files[i]).stem().string() + "_corners.png");
        writePng(drawn, name);
      }
    }

    const std::unique_ptr<Camera> camera = createCamera(LensModel::Pinhole, result.intrinsics, CameraMount{});
    writeFileAtomic(config.output, cameraToJson(*camera, "chessboard calibration"));

    const CameraIntrinsics& in = result.intrinsics;
    out << std::fixed << std::setprecision(3);
    out << "calibrated from " << result.images_used << " of " << config.images.size() << " images (" << in.width << "x"
        << in.height << ", the most common size)\n";
    for (const std::string& f : result.fitted) out << "  fitted " << f << "\n";
    for (const std::string& r : result.rejected) out << "  skipped " << r << "\n";
    out << "focal " << in.fx << ", " << in.fy << " px; principal point " << in.cx << ", " << in.cy << " px\n";
    out << std::setprecision(6) << "distortion k1 k2 p1 p2 k3: " << in.distortion[0] << " " << in.distortion[1] << " "
        << in.distortion[2] << " " << in.distortion[3] << " " << in.distortion[4] << "\n";
    out << std::setprecision(4) << "RMS reprojection error " << result.rms_reprojection_px << " px\n";
    out << "wrote " << config.output
        << ": the mount (x, y, height_m, tilt_deg, roll_deg, yaw_deg) is a default, not measured: fill it in "
           "(the tilt can be found from two ground-parallel lines, Wallace 1985, 3.5.2)\n";
    if (!config.corners_dir.empty()) out << "corners drawn in " << config.corners_dir << "\n";
    return 0;
  });
}

int runCalibrateTilt(const std::string& camera_file, const Segment2& a, const Segment2& b, const std::string& output,
                     std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    const auto camera = loadCamera(camera_file);
    const double tilt = tiltFromParallelLines(camera->intrinsics(), a, b);
    char line[160];
    std::snprintf(line, sizeof line, "tilt %.3f degrees below the horizon (the file says %.3f)\n", radToDeg(tilt),
                  radToDeg(camera->mount().tilt_rad));
    out << line;
    if (!output.empty()) {
      CameraMount mount = camera->mount();
      mount.tilt_rad = tilt;
      writeFileAtomic(output, cameraToJson(*createCamera(camera->model(), camera->intrinsics(), mount)));
      out << "wrote " << output << "\n";
    }
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav rectify` and `mapnav calibrate ...` -------------------------------

namespace {

void addRectify(CLI::App& app, Commands& commands) {
  auto* rectify = commands.hold<RectifyConfig>();
  CLI::App* rc = app.add_subcommand("rectify", "Warp a camera frame to a top view of the ground (Wallace 1985, 3.5.1)");
  rc->add_option("image", rectify->image, "Camera frame (PNG or JPEG)")->required()->check(CLI::ExistingFile);
  rc->add_option("--camera", rectify->camera, "Camera file")->required()->check(CLI::ExistingFile);
  rc->add_option("--x-min", rectify->options.x_min_m, "Nearest ground ahead, m")->capture_default_str();
  rc->add_option("--x-max", rectify->options.x_max_m, "Farthest ground ahead, m")->capture_default_str();
  rc->add_option("--y-min", rectify->options.y_min_m, "Rightmost ground, m (right negative)")->capture_default_str();
  rc->add_option("--y-max", rectify->options.y_max_m, "Leftmost ground, m")->capture_default_str();
  rc->add_option("--resolution", rectify->options.metres_per_pixel, "Metres per output pixel")->capture_default_str();
  rc->add_option("-o,--output", rectify->output, "Top view to write (PNG): far at the top, left on the left")->required();
  rc->add_flag("--undistort", rectify->undistort,
               "Write the frame undistorted instead (same size, as the camera's ideal pin-hole would see it: "
               "straight lines straight); the ground options are then unused");
  rc->callback(commands.choose([rectify](std::ostream& out, std::ostream& err) { return runRectify(*rectify, out, err); }));
}

void addChessboard(CLI::App& calibrate, Commands& commands) {
  auto* chessboard = commands.hold<CalibrateChessboardConfig>();
  auto* board = commands.hold<std::string>();
  *board = "9x6";
  CLI::App* cb = calibrate.add_subcommand("chessboard", "Intrinsics from chessboard photos; reports the reprojection error");
  cb->add_option("images", chessboard->images, "Photos of the board (PNG or JPEG)")->required()->check(CLI::ExistingFile);
  cb->add_option("--board", *board, "Inner corners COLSxROWS")->default_val("9x6");
  cb->add_option("--square", chessboard->square_m, "Square size, m")->default_val(0.025)->check(commands.numberCheck(CLI::PositiveNumber));
  cb->add_option("-o,--output", chessboard->output, "Camera file to write (mapnav-camera/1; fill in the mount)")->required();
  cb->add_option("--corners", chessboard->corners_dir, "Folder to draw the detected corners into");
  cb->add_option("--size-tolerance", chessboard->size_tolerance_px,
                 "Photos within this many pixels of the most common size are cut or padded to it; others are skipped")
      ->capture_default_str()
      ->check(commands.numberCheck(CLI::NonNegativeNumber));
  cb->callback(commands.choose([chessboard, board](std::ostream& out, std::ostream& err) {
    const auto x = board->find('x');
    try {
      if (x == std::string::npos) throw std::invalid_argument(*board);
      chessboard->cols = std::stoi(board->substr(0, x));
      chessboard->rows = std::stoi(board->substr(x + 1));
    } catch (const std::exception&) {
      throw InvalidInput("--board \"" + *board + "\": expected COLSxROWS, e.g. 9x6");
    }
    return runCalibrateChessboard(*chessboard, out, err);
  }));
}

void addTilt(CLI::App& calibrate, Commands& commands) {
  struct Tilt {
    std::string camera, output;
    std::vector<std::string> lines;
  };
  auto* tilt = commands.hold<Tilt>();
  CLI::App* tl = calibrate.add_subcommand("tilt", "Camera tilt from the vanishing point of two ground-parallel lines (the paper's poles)");
  tl->add_option("--camera", tilt->camera, "Camera file (its intrinsics are used)")->required()->check(CLI::ExistingFile);
  tl->add_option("--line", tilt->lines, "A ground-parallel line's image end points U1,V1,U2,V2 (give two)")->required()->expected(2);
  tl->add_option("-o,--output", tilt->output, "Write the camera with this tilt");
  tl->callback(commands.choose([tilt](std::ostream& out, std::ostream& err) {
    std::vector<Segment2> lines;
    for (const std::string& text : tilt->lines) {
      const auto v = parseNumbers("--line", text, 4, 4, "U1,V1,U2,V2 (pixels)");
      lines.push_back(Segment2{Vec2(v[0], v[1]), Vec2(v[2], v[3])});
    }
    return runCalibrateTilt(tilt->camera, lines.at(0), lines.at(1), tilt->output, out, err);
  }));
}

}  // namespace

void registerVisionCommands(CLI::App& app, Commands& commands) {
  addRectify(app, commands);
  CLI::App* calibrate = app.add_subcommand("calibrate", "Camera calibration (Wallace 1985, 3.5.2; OpenCV chessboards)");
  calibrate->require_subcommand(1);
  addChessboard(*calibrate, commands);
  addTilt(*calibrate, commands);
}

}  // namespace mapnav::cli
