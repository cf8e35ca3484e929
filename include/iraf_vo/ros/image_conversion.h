// ROS glue (not part of the ROS-free core): sensor_msgs/Image and sensor_msgs/CompressedImage -> 8-bit grayscale
// cv::Mat, and an 8-bit cv::Mat -> sensor_msgs/Image.
#pragma once

#include <opencv2/core.hpp>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <string>

namespace iraf_vo {

/// Encodings the pipeline accepts; each becomes mono8 (mono16 through cv_bridge, i.e. scaled by 255/65535).
bool isSupportedEncoding(const std::string& encoding);
/// Comma-separated list of isSupportedEncoding() encodings, for error messages.
const char* supportedEncodings();

/// Converts a message to a CV_8UC1 image (shares data with the message when it already is mono8).
/// Returns false and fills `error` (naming the encoding / size problem) for anything unusable:
/// unsupported encoding, zero width or height, data shorter than step * height.
bool toMono8(const sensor_msgs::ImageConstPtr& msg, cv::Mat* gray, std::string* error);

/// Decodes a sensor_msgs/CompressedImage (image_transport's `compressed`: jpeg or png, 8 or 16 bit, mono or
/// colour in BGR order) with cv::imdecode into a new CV_8UC1 image (16 bit -> value / 256, colour -> gray).
/// false + *error naming the format for empty data, garbage, or compressedDepth (not supported).
bool toMono8(const sensor_msgs::CompressedImage& msg, cv::Mat* gray, std::string* error);
/// An 8-bit image as a message (cv_bridge copy): CV_8UC1 -> mono8, CV_8UC3 -> bgr8. Throws std::invalid_argument
/// for other types.
sensor_msgs::ImagePtr toImageMsg(const cv::Mat& image, const std_msgs::Header& header);

}  // namespace iraf_vo
