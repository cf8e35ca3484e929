// iraf_vo_degrade: applies the simulator's photometric events to a real ASL sequence (e.g. EuRoC),
// keeping timestamps, calibration and ground truth.
//
//   iraf_vo_degrade DIR OUT --profile dark|overexposed|flicker|mixed [--seed S]
//
// Copies mav0/cam0/sensor.yaml, any groundtruth*/ folder, mav0/state_groundtruth_estimate0/ (and the
// other mav0 sensors), writes OUT/mav0/cam0/data.csv + data/*.png and OUT/events.csv. Missing or
// unreadable images are reported and skipped; a missing dataset exits non-zero.
#include <iostream>
#include <string>

#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/sequence.h"

namespace {
void usage(std::ostream& os) {
  os << "usage: iraf_vo_degrade DIR OUT --profile " << iraf_vo::photometricPresetNames() << " [--seed S]\n"
        "  DIR: ASL sequence (DIR/mav0/cam0/data.csv + data/), OUT: output folder (same layout)\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::string in_dir, out_dir, profile;
  long seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    }
    if (a == "--profile" || a == "--seed") {
      if (i + 1 >= argc) {
        std::cerr << "iraf_vo_degrade: " << a << " needs a value\n";
        return 2;
      }
      const std::string v = argv[++i];
      if (a == "--profile") {
        profile = v;
      } else {
        try {
          size_t used = 0;
          seed = std::stol(v, &used);
          if (used != v.size() || seed < 0) throw std::out_of_range("seed");
        } catch (const std::exception&) {
          std::cerr << "iraf_vo_degrade: --seed must be a non-negative integer (got '" << v << "')\n";
          return 2;
        }
      }
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "iraf_vo_degrade: unknown option '" << a << "'\n";
      usage(std::cerr);
      return 2;
    } else if (in_dir.empty()) {
      in_dir = a;
    } else if (out_dir.empty()) {
      out_dir = a;
    } else {
      std::cerr << "iraf_vo_degrade: unexpected argument '" << a << "'\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (in_dir.empty() || out_dir.empty() || profile.empty()) {
    std::cerr << "iraf_vo_degrade: DIR, OUT and --profile are required\n";
    usage(std::cerr);
    return 2;
  }
  // Count the rows first so the event frame ranges scale with the sequence length.
  std::vector<std::pair<int64_t, std::string>> rows;
  std::string err;
  if (!iraf_vo::readAslCsv(in_dir + "/mav0/cam0/data.csv", &rows, &err)) {
    std::cerr << "iraf_vo_degrade: " << in_dir << ": not an ASL sequence (" << err << ")\n";
    return 1;
  }
  iraf_vo::PhotometricParams photometric;
  if (!iraf_vo::photometricPreset(profile, static_cast<int>(rows.size()), true, static_cast<uint64_t>(seed),
                                  &photometric)) {
    std::cerr << "iraf_vo_degrade: unknown --profile '" << profile << "' (use " << iraf_vo::photometricPresetNames()
              << ")\n";
    return 2;
  }
  iraf_vo::DegradeReport rep;
  bool ok = false;
  try {
    ok = iraf_vo::degradeAslSequence(in_dir, out_dir, photometric, &rep, &err);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) {
    std::cerr << "iraf_vo_degrade: " << err << "\n";
    return 1;
  }
  std::cout << "iraf_vo_degrade: " << profile << ": wrote " << rep.written << " of " << rep.images << " images to "
            << out_dir << " (" << rep.skipped << " missing/unreadable skipped); copied:";
  for (const auto& c : rep.copied) std::cout << " " << c;
  std::cout << "\n";
  return rep.written > 0 ? 0 : 1;
}
