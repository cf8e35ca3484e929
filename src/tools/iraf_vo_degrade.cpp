// iraf_vo_degrade: passes a real ASL sequence (e.g. EuRoC) through the simulator's camera model with one
// of its light profiles (the 8-bit images taken as linear radiance at the reference exposure), keeping
// timestamps, calibration and ground truth.
//
//   iraf_vo_degrade DIR OUT --profile clean|dark|...|glare [--seed S] [--reference-exposure SEC (0.01)]
//
// Copies mav0/cam0/sensor.yaml, any groundtruth*/ folder, mav0/state_groundtruth_estimate0/ (and the
// other mav0 sensors), writes OUT/mav0/cam0/data.csv + data/*.png, OUT/events.csv and OUT/exposure.csv.
// A stereo sequence's mav0/cam1 is degraded too: the same light, cam0's exposure and gain, its own noise.
// Missing or unreadable images are reported and skipped; a missing dataset exits non-zero.
#include <iostream>
#include <limits>
#include <string>

#include <algorithm>
#include <vector>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/sim/asl_degrade.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/sequence.h"

int main(int argc, char** argv) {
  std::string in_dir, out_dir, profile;
  int seed = 1;
  double reference_exposure = 0.01;
  iraf_vo::CommandLine cli("iraf_vo_degrade",
                           "Passes a real ASL sequence through the simulator's camera model with a light profile.");
  cli.positional("DIR", &in_dir, "ASL sequence (DIR/mav0/cam0/data.csv + data/)");
  cli.positional("OUT", &out_dir, "output folder (same layout)");
  cli.option("--profile", "P", &profile, iraf_vo::lightProfileNames());
  cli.option("--seed", "S", &seed, 0, std::numeric_limits<int>::max(), "random seed (default 1)");
  cli.option("--reference-exposure", "SEC", &reference_exposure, 1e-6, 1.0,
             "the exposure the images were taken with (default 0.01)");
  cli.require("--profile");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  // Count the rows first so the event frame ranges scale with the sequence length.
  std::vector<std::pair<int64_t, std::string>> rows;
  std::string err;
  if (!iraf_vo::readAslCsv(in_dir + "/mav0/cam0/data.csv", &rows, &err)) {
    std::cerr << "iraf_vo_degrade: " << in_dir << ": not an ASL sequence (" << err << ")\n";
    return 1;
  }
  // Frame rate from the median time step (durations such as the blackout's are in seconds).
  double rate_hz = 20.0;
  if (rows.size() > 2) {
    std::vector<int64_t> dt;
    for (size_t i = 1; i < rows.size(); ++i) dt.push_back(rows[i].first - rows[i - 1].first);
    std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
    if (dt[dt.size() / 2] > 0) rate_hz = 1e9 / static_cast<double>(dt[dt.size() / 2]);
  }
  iraf_vo::LightProfile light;
  if (!iraf_vo::lightProfile(profile, static_cast<int>(rows.size()), rate_hz, reference_exposure, true,
                             static_cast<uint64_t>(seed), &light)) {
    std::cerr << "iraf_vo_degrade: unknown --profile '" << profile << "' (use " << iraf_vo::lightProfileNames()
              << ")\n";
    return 2;
  }
  iraf_vo::DegradeReport rep;
  bool ok = false;
  try {
    ok = iraf_vo::degradeAslSequence(in_dir, out_dir, light, &rep, &err);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) {
    std::cerr << "iraf_vo_degrade: " << err << "\n";
    return 1;
  }
  std::cout << "iraf_vo_degrade: " << profile << ": wrote " << rep.written << " of " << rep.images << " images to "
            << out_dir << " (" << rep.skipped << " missing/unreadable skipped)";
  if (rep.right_images > 0)
    std::cout << ", cam1 " << rep.right_written << " of " << rep.right_images << " (" << rep.right_skipped
              << " skipped)";
  std::cout << "; copied:";
  for (const auto& c : rep.copied) std::cout << " " << c;
  std::cout << "\n";
  return rep.written > 0 ? 0 : 1;
}
