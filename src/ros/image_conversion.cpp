#include "iraf_vo/ros/image_conversion.h"

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgcodecs.hpp>
#include <sensor_msgs/image_encodings.h>

#include <stdexcept>

#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/png_gray8.h"

namespace iraf_vo {

namespace enc = sensor_msgs::image_encodings;

bool isSupportedEncoding(const std::string& e) {
  return e == enc::MONO8 || e == enc::MONO16 || e == enc::BGR8 || e == enc::RGB8 || e == enc::BGRA8;
}

const char* supportedEncodings() { return "mono8, mono16, bgr8, rgb8, bgra8"; }

bool toMono8(const sensor_msgs::ImageConstPtr& msg, cv::Mat* gray, std::string* error) {
  if (!msg) {
    *error = "null image message";
    return false;
  }
  if (!isSupportedEncoding(msg->encoding)) {
    *error = "unsupported encoding '" + msg->encoding + "' (supported: " + supportedEncodings() + ")";
    return false;
  }
  if (msg->width == 0 || msg->height == 0) {
    *error = "empty image (" + std::to_string(msg->width) + "x" + std::to_string(msg->height) + ")";
    return false;
  }
  const size_t min_step = static_cast<size_t>(msg->width) * enc::numChannels(msg->encoding) *
                          (enc::bitDepth(msg->encoding) / 8);
  if (msg->step < min_step || msg->data.size() < static_cast<size_t>(msg->step) * msg->height) {
    *error = "inconsistent image: " + std::to_string(msg->width) + "x" + std::to_string(msg->height) +
             " step " + std::to_string(msg->step) + " with " + std::to_string(msg->data.size()) + " data bytes";
    return false;
  }
  try {
    if (msg->encoding == enc::MONO8) {
      *gray = cv_bridge::toCvShare(msg, enc::MONO8)->image;
    } else {
      *gray = cv_bridge::toCvCopy(msg, enc::MONO8)->image;
    }
  } catch (const cv_bridge::Exception& e) {
    *error = std::string("cv_bridge: ") + e.what();
    return false;
  } catch (const cv::Exception& e) {
    *error = std::string("OpenCV: ") + e.what();
    return false;
  }
  return true;
}

bool toMono8(const sensor_msgs::CompressedImage& msg, cv::Mat* gray, std::string* error) {
  const std::string what = "compressed image (format '" + msg.format + "', " + std::to_string(msg.data.size()) + " bytes)";
  if (msg.format.find("compressedDepth") != std::string::npos) {
    *error = what + ": compressedDepth (depth images) is not supported; use the 'compressed' transport (jpeg / png)";
    return false;
  }
  if (msg.data.empty()) {
    *error = what + ": no data";
    return false;
  }
  std::string opencv_error;
  const cv::Mat raw = decodeImage(msg.data.data(), msg.data.size(), &opencv_error);
  if (!opencv_error.empty()) {
    *error = what + ": OpenCV cannot decode it: " + opencv_error;
    return false;
  }
  if (raw.empty()) {
    *error = what + ": cannot decode (not a valid jpeg / png)";
    return false;
  }
  std::string err;
  if (!toGray8(raw, gray, &err)) {
    *error = what + ": " + err;
    return false;
  }
  return true;
}

sensor_msgs::ImagePtr toImageMsg(const cv::Mat& image, const std_msgs::Header& header) {
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3)
    throw std::invalid_argument("toImageMsg: expected CV_8UC1 or CV_8UC3, got type " + std::to_string(image.type()));
  return cv_bridge::CvImage(header, image.channels() == 1 ? enc::MONO8 : enc::BGR8, image).toImageMsg();
}

}  // namespace iraf_vo
