// iraf_vo_asl_to_bag DIR OUT.bag [--topic /cam0/image_raw] [--frame-id cam0] [--camera cam0] [--compression none|bz2|lz4]
//                    [--compressed[=png|jpeg]] [--jpeg-quality 1..100]
//                    [--right-camera cam1] [--right-topic /cam1/image_raw] [--right-frame-id cam1]
// Converts an ASL / EuRoC / TUM-VI image folder (DIR, DIR/mav0 or DIR/mav0/cam0) into a rosbag of mono8
// sensor_msgs/Image messages stamped with the data.csv timestamps; --compressed writes sensor_msgs/CompressedImage
// (png: lossless, default; jpeg) on TOPIC/compressed as recorded camera bags carry them. A stereo folder (DIR/mav0/cam1
// present) gets its right camera on --right-topic too.
#include <cstdio>
#include <string>
#include <vector>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/ros/bag_reader.h"

int main(int argc, char** argv) {
  iraf_vo::AslToBagOptions opt;
  std::string dir, bag, image_format;
  iraf_vo::CommandLine cli("iraf_vo_asl_to_bag", "Converts an ASL image folder into a rosbag of sensor_msgs/Image.");
  cli.positional("DIR", &dir, "ASL folder: DIR, DIR/mav0 or DIR/mav0/cam0 holding data.csv + data/*.png");
  cli.positional("OUT.bag", &bag, "the bag to write");
  cli.option("--topic", "T", &opt.topic, "image topic (default " + opt.topic + ")");
  cli.option("--frame-id", "ID", &opt.frame_id, "header frame_id (default " + opt.frame_id + ")");
  cli.option("--camera", "NAME", &opt.camera, "camera folder name (default " + opt.camera + ")");
  cli.option("--compression", "C", &opt.compression,
             "rosbag chunk compression none | bz2 | lz4 (independent of --compressed)");
  cli.optionalValue("--compressed", "png|jpeg", &image_format, "png",
                    "sensor_msgs/CompressedImage on TOPIC/compressed (png = lossless, default; or jpeg)");
  cli.option("--jpeg-quality", "Q", &opt.jpeg_quality, 1, 100,
             "JPEG quality (default " + std::to_string(opt.jpeg_quality) + ")");
  cli.option("--right-camera", "NAME", &opt.right_camera,
             "right camera folder, written too when it exists (default " + opt.right_camera + "; \"\" = never)");
  cli.option("--right-topic", "T", &opt.right_topic, "right image topic (default " + opt.right_topic + ")");
  cli.option("--right-frame-id", "ID", &opt.right_frame_id,
             "right header frame_id (default " + opt.right_frame_id + ")");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (!image_format.empty()) {
    if (image_format != "png" && image_format != "jpeg") {
      std::fprintf(stderr, "iraf_vo_asl_to_bag: --compressed=%s: expected --compressed, --compressed=png or "
                   "--compressed=jpeg\n", image_format.c_str());
      return 2;
    }
    opt.image_format = image_format;
  }
  std::string err;
  std::vector<std::string> warnings;
  size_t n_right = 0;
  const size_t n = iraf_vo::aslToBag(dir, bag, opt, &err, &warnings, &n_right);
  for (size_t i = 0; i < warnings.size() && i < 20; ++i) std::fprintf(stderr, "warning: %s\n", warnings[i].c_str());
  if (warnings.size() > 20) std::fprintf(stderr, "warning: ... %zu more\n", warnings.size() - 20);
  if (n == 0) {
    std::fprintf(stderr, "iraf_vo_asl_to_bag: %s\n", err.c_str());
    return 1;
  }
  const std::string suffix = opt.image_format == "raw" ? "" : "/compressed";
  const std::string right = n_right == 0 ? "" : " and " + std::to_string(n_right) + " on " + opt.right_topic + suffix +
                                                    " (frame_id " + opt.right_frame_id + ")";
  std::printf("wrote %zu %s images to %s on %s (frame_id %s)%s, %zu skipped\n", n,
              opt.image_format == "raw" ? "mono8" : opt.image_format.c_str(), bag.c_str(),
              (opt.topic + suffix).c_str(), opt.frame_id.c_str(), right.c_str(), warnings.size());
  return 0;
}
