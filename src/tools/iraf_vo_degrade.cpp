// iraf_vo_degrade: applies the simulator's photometric events to a real ASL sequence (e.g. EuRoC),
// keeping timestamps, calibration and ground truth.
//
//   iraf_vo_degrade DIR OUT --profile dark|overexposed|flicker|mixed [--seed S]
//
// Copies mav0/cam0/sensor.yaml, any groundtruth*/ folder, mav0/state_groundtruth_estimate0/ (and the
// other mav0 sensors), writes OUT/mav0/cam0/data.csv + data/*.png and OUT/events.csv. Missing or
// unreadable images are reported and skipped; a missing dataset exits non-zero.
#include <iostream>
#include <limits>
#include <string>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/sequence.h"

int main(int argc, char** argv) {
  std::string in_dir, out_dir, profile;
  int seed = 1;
  iraf_vo::CommandLine cli("iraf_vo_degrade",
                           "Applies the simulator's photometric events to a real ASL sequence (same layout in OUT).");
  cli.positional("DIR", &in_dir, "ASL sequence (DIR/mav0/cam0/data.csv + data/)");
  cli.positional("OUT", &out_dir, "output folder (same layout)");
  cli.option("--profile", "P", &profile, std::string(iraf_vo::photometricPresetNames()));
  cli.option("--seed", "S", &seed, 0, std::numeric_limits<int>::max(), "random seed of the events (default 1)");
  cli.require("--profile");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
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
