// Degrading real ASL sequences (ROS-free): the images of mav0/cam0 (and of mav0/cam1 when the sequence is
// stereo) pass through the photometric events or the simulator's camera model; timestamps, calibration
// and ground truth are kept.
#pragma once

#include <string>
#include <vector>

#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/photometric.h"

namespace iraf_vo {

struct DegradeReport {
  int images = 0;     // rows of data.csv
  int written = 0;
  int skipped = 0;    // missing/unreadable images (reported on stderr)
  int right_images = 0, right_written = 0, right_skipped = 0;  // the same for mav0/cam1 (stereo sequences)
  std::vector<std::string> copied;  // ground-truth / calibration files copied (relative paths)
};

/// Applies the photometric events to every image of the ASL sequence in_dir (mav0/cam0/data.csv +
/// data/), writing out_dir with the same layout and timestamps; copies mav0/cam0/sensor.yaml, any
/// groundtruth/ folder, mav0/state_groundtruth_estimate0/, the other mav0 sensors' csv/yaml files,
/// and top-level files. A stereo sequence (mav0/cam1/data.csv) gets cam1 degraded too: each image with
/// the events of the cam0 frame nearest in time and its own noise (cam1/sensor.yaml copied).
/// Returns false (and sets *error) when in_dir has no mav0/cam0/data.csv.
bool degradeAslSequence(const std::string& in_dir, const std::string& out_dir, const PhotometricParams& photometric,
                        DegradeReport* report, std::string* error);

/// The same with the camera model: each real 8-bit image is taken as linear radiance in DN at the
/// profile's reference exposure, lit, blurred along the image motion (phase correlation with the previous
/// image) by the exposure time beyond the reference, and exposed; also writes OUT/exposure.csv. The
/// flashlight's angles come from mav0/cam0/sensor.yaml when it loads (no depth: no distance fall-off).
/// cam1 of a stereo sequence: the same light, the exposure, gain and image motion of the cam0 frame
/// nearest in time (as paired cameras share one auto-exposure), its own sensor noise.
bool degradeAslSequence(const std::string& in_dir, const std::string& out_dir, const LightProfile& light,
                        DegradeReport* report, std::string* error);

}  // namespace iraf_vo
