// Trajectories (stamp in seconds + pose T_W_C) and their file formats (ROS-free):
//  - TUM:   "t tx ty tz qx qy qz qw" per line, whitespace separated, '#' comments; t in seconds, or in
//           nanoseconds (auto-detected when t > 1e12). Written with 9 decimals (readable by evo: evo_ape tum).
//  - EuRoC: state_groundtruth_estimate0/data.csv, "t_ns, p_x, p_y, p_z, q_w, q_x, q_y, q_z, ..." (body pose
//           T_W_B; extra columns ignored). The camera pose is T_W_C = T_W_B * T_BS.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace iraf_vo {

struct Trajectory {
  std::vector<double> stamps;            ///< seconds, strictly increasing after reading
  std::vector<Eigen::Isometry3d> poses;  ///< T_W_C (camera / sensor to world)

  size_t size() const { return stamps.size(); }
  bool empty() const { return stamps.empty(); }
  void clear() {
    stamps.clear();
    poses.clear();
  }
  void push_back(double t, const Eigen::Isometry3d& T) {
    stamps.push_back(t);
    poses.push_back(T);
  }
  /// Sorts by time and drops duplicated stamps (keeps the first). Returns the number dropped.
  size_t sortAndUnique();
};

/// Reads a TUM file. Malformed lines / non-unit or NaN quaternions are reported in *warnings (with line
/// number) and skipped; false + *error (naming the file) when it cannot be opened or has no valid pose.
/// Quaternions are normalized.
bool readTumTrajectory(const std::string& path, Trajectory* traj, std::string* error,
                       std::vector<std::string>* warnings = nullptr);

/// Reads an EuRoC ground-truth csv and applies T_BS (sensor to body): T_W_C = T_W_B * T_BS.
bool readEurocGroundTruth(const std::string& path, Trajectory* traj, std::string* error,
                          const Eigen::Matrix4d& T_BS = Eigen::Matrix4d::Identity(),
                          std::vector<std::string>* warnings = nullptr);

/// Auto-detects the format from the first data line (commas -> EuRoC csv, otherwise TUM).
/// A directory is accepted too: DIR[/mav0]/state_groundtruth_estimate0/data.csv (EuRoC) or DIR[/mav0]/mocap0/data.csv
/// (TUM-VI, same csv layout).
bool readTrajectory(const std::string& path, Trajectory* traj, std::string* error,
                    const Eigen::Matrix4d& T_BS = Eigen::Matrix4d::Identity(),
                    std::vector<std::string>* warnings = nullptr);

/// Writes TUM format ("# timestamp tx ty tz qx qy qz qw" header, stamps with 9 decimals). false + *error.
bool writeTumTrajectory(const std::string& path, const Trajectory& traj, std::string* error);

}  // namespace iraf_vo
