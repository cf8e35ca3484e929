// iraf_vo_asl_to_bag DIR OUT.bag [--topic /cam0/image_raw] [--frame-id cam0] [--camera cam0] [--compression none|bz2|lz4]
//                    [--compressed[=png|jpeg]] [--jpeg-quality 1..100]
// Converts an ASL / EuRoC / TUM-VI image folder (DIR, DIR/mav0 or DIR/mav0/cam0) into a rosbag of mono8
// sensor_msgs/Image messages stamped with the data.csv timestamps; --compressed writes sensor_msgs/CompressedImage
// (png: lossless, default; jpeg) on TOPIC/compressed as recorded camera bags carry them.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "iraf_vo/ros/bag_reader.h"

namespace {
void usage(FILE* f) {
  std::fprintf(f,
               "usage: iraf_vo_asl_to_bag DIR OUT.bag [--topic /cam0/image_raw] [--frame-id cam0] [--camera cam0]\n"
               "                          [--compression none|bz2|lz4] [--compressed[=png|jpeg]] [--jpeg-quality 95]\n"
               "  DIR  ASL folder: DIR, DIR/mav0 or DIR/mav0/cam0 holding data.csv + data/*.png\n"
               "  --compressed  sensor_msgs/CompressedImage on TOPIC/compressed (png = lossless, default; or jpeg)\n"
               "  --compression  rosbag chunk compression (independent of --compressed)\n");
}
}  // namespace

int main(int argc, char** argv) {
  iraf_vo::AslToBagOptions opt;
  std::vector<std::string> pos;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "iraf_vo_asl_to_bag: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--topic") {
      opt.topic = value("--topic");
    } else if (a == "--frame-id") {
      opt.frame_id = value("--frame-id");
    } else if (a == "--camera") {
      opt.camera = value("--camera");
    } else if (a == "--compression") {
      opt.compression = value("--compression");
    } else if (a == "--compressed" || a.rfind("--compressed=", 0) == 0) {
      opt.image_format = a == "--compressed" ? "png" : a.substr(13);
      if (opt.image_format != "png" && opt.image_format != "jpeg") {
        std::fprintf(stderr, "iraf_vo_asl_to_bag: %s: expected --compressed, --compressed=png or --compressed=jpeg\n", a.c_str());
        return 2;
      }
    } else if (a == "--jpeg-quality") {
      const std::string q = value("--jpeg-quality");
      char* end = nullptr;
      const long v = std::strtol(q.c_str(), &end, 10);
      if (q.empty() || *end != '\0' || v < 1 || v > 100) {
        std::fprintf(stderr, "iraf_vo_asl_to_bag: --jpeg-quality '%s': expected an integer 1..100\n", q.c_str());
        return 2;
      }
      opt.jpeg_quality = static_cast<int>(v);
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "iraf_vo_asl_to_bag: unknown option '%s'\n", a.c_str());
      usage(stderr);
      return 2;
    } else {
      pos.push_back(a);
    }
  }
  if (pos.size() != 2) {
    std::fprintf(stderr, "iraf_vo_asl_to_bag: expected 2 positional arguments (DIR OUT.bag), got %zu\n", pos.size());
    usage(stderr);
    return 2;
  }
  std::string err;
  std::vector<std::string> warnings;
  const size_t n = iraf_vo::aslToBag(pos[0], pos[1], opt, &err, &warnings);
  for (size_t i = 0; i < warnings.size() && i < 20; ++i) std::fprintf(stderr, "warning: %s\n", warnings[i].c_str());
  if (warnings.size() > 20) std::fprintf(stderr, "warning: ... %zu more\n", warnings.size() - 20);
  if (n == 0) {
    std::fprintf(stderr, "iraf_vo_asl_to_bag: %s\n", err.c_str());
    return 1;
  }
  const std::string topic = opt.image_format == "raw" ? opt.topic : opt.topic + "/compressed";
  std::printf("wrote %zu %s images to %s on %s (frame_id %s, %zu skipped)\n", n,
              opt.image_format == "raw" ? "mono8" : opt.image_format.c_str(), pos[1].c_str(), topic.c_str(),
              opt.frame_id.c_str(), warnings.size());
  return 0;
}
