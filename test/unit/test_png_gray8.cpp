// The grayscale PNG fast path (io/png_gray8.h) against OpenCV's decoder: every filter type, odd sizes, split
// IDAT chunks and metadata chunks give OpenCV's pixels; other PNGs and damaged files are left to OpenCV; the
// shared EuRoC frames decode to the same bytes as cv::imread.
#include <gtest/gtest.h>
#include <libdeflate.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/png_gray8.h"

namespace {

using Bytes = std::vector<uint8_t>;

void putBigEndian32(Bytes* b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b->push_back(static_cast<uint8_t>(v >> s));
}

void putChunk(Bytes* png, const char* type, const Bytes& body) {
  putBigEndian32(png, static_cast<uint32_t>(body.size()));
  Bytes typed(type, type + 4);
  typed.insert(typed.end(), body.begin(), body.end());
  png->insert(png->end(), typed.begin(), typed.end());
  putBigEndian32(png, libdeflate_crc32(0, typed.data(), typed.size()));
}

// The PNG spec's Paeth predictor, written as the spec states it (independent of the decoder's branch-free one).
int paethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  if (pb <= pc) return b;
  return c;
}

struct PngOptions {
  std::vector<int> filters{0, 1, 2, 3, 4};  // row r uses filters[r % size]
  size_t idat_bytes = 1 << 20;              // IDAT chunk size
  bool text_chunks = false;                 // tEXt before and after the image data
  uint8_t bit_depth = 8, color_type = 0, interlace = 0;
  const char* extra_chunk = nullptr;        // a chunk inserted before IDAT (e.g. "tRNS", "gAMA")
};

// A minimal PNG encoder (8-bit gray) with the filter type of every row chosen by the test.
Bytes encodeGrayPng(const cv::Mat& img, const PngOptions& o) {
  Bytes raw;
  for (int r = 0; r < img.rows; ++r) {
    const int type = o.filters[r % o.filters.size()];
    raw.push_back(static_cast<uint8_t>(type));
    for (int i = 0; i < img.cols; ++i) {
      const int x = img.at<uint8_t>(r, i);
      const int a = i > 0 ? img.at<uint8_t>(r, i - 1) : 0;
      const int b = r > 0 ? img.at<uint8_t>(r - 1, i) : 0;
      const int c = r > 0 && i > 0 ? img.at<uint8_t>(r - 1, i - 1) : 0;
      const int pred = type == 0 ? 0 : type == 1 ? a : type == 2 ? b : type == 3 ? (a + b) / 2 : paethPredictor(a, b, c);
      raw.push_back(static_cast<uint8_t>(x - pred));
    }
  }
  libdeflate_compressor* z = libdeflate_alloc_compressor(6);
  Bytes zlib(libdeflate_zlib_compress_bound(z, raw.size()));
  zlib.resize(libdeflate_zlib_compress(z, raw.data(), raw.size(), zlib.data(), zlib.size()));
  libdeflate_free_compressor(z);

  Bytes png{137, 80, 78, 71, 13, 10, 26, 10};
  Bytes ihdr;
  putBigEndian32(&ihdr, static_cast<uint32_t>(img.cols));
  putBigEndian32(&ihdr, static_cast<uint32_t>(img.rows));
  ihdr.insert(ihdr.end(), {o.bit_depth, o.color_type, 0, 0, o.interlace});
  putChunk(&png, "IHDR", ihdr);
  const Bytes text{'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'h', 'i'};
  if (o.text_chunks) putChunk(&png, "tEXt", text);
  if (o.extra_chunk) putChunk(&png, o.extra_chunk, Bytes{0, 0, 0, 1});
  for (size_t p = 0; p < zlib.size(); p += o.idat_bytes)
    putChunk(&png, "IDAT", Bytes(zlib.begin() + p, zlib.begin() + std::min(zlib.size(), p + o.idat_bytes)));
  if (o.text_chunks) putChunk(&png, "tEXt", text);
  putChunk(&png, "IEND", Bytes());
  return png;
}

// Camera-like content: smooth shading, edges and noise, so every Paeth branch is taken.
cv::Mat testImage(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-12, 12);
  cv::Mat img(rows, cols, CV_8UC1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int v = (r * 3 + c * 2) % 200 + ((c / 5 + r / 7) % 2) * 40 + noise(rng);
      img.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(v);
    }
  return img;
}

cv::Mat openCvDecode(const Bytes& png) { return cv::imdecode(png, cv::IMREAD_UNCHANGED); }

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

}  // namespace

TEST(PngGray8, EveryFilterTypeAndSizeGivesOpenCvsPixels) {
  // Blocks of 16 rows take the SIMD front (every filter type per lane, widths below / at / above 16 lanes).
  const std::vector<std::vector<int>> filter_sets = {{0}, {1}, {2}, {3}, {4}, {4, 3, 2, 1, 0}, {4, 4, 1, 4, 3, 4, 2, 0, 4}};
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(2, 3), cv::Size(7, 5), cv::Size(64, 33), cv::Size(753, 21),
                              cv::Size(1, 40), cv::Size(15, 17), cv::Size(16, 32), cv::Size(17, 49), cv::Size(301, 64)})
    for (const auto& filters : filter_sets) {
      const cv::Mat img = testImage(size.height, size.width, size.area());
      PngOptions o;
      o.filters = filters;
      o.idat_bytes = 100;  // many IDAT chunks
      o.text_chunks = true;
      const Bytes png = encodeGrayPng(img, o);
      const cv::Mat ref = openCvDecode(png);
      ASSERT_TRUE(sameImage(ref, img)) << "test encoder broken at " << size << " filter " << filters[0];
      cv::Mat ours;
      ASSERT_TRUE(iraf_vo::decodeGray8Png(png.data(), png.size(), &ours)) << size << " filter " << filters[0];
      EXPECT_TRUE(sameImage(ours, ref)) << size << " filter " << filters[0];
    }
}

TEST(PngGray8, OpenCvsOwnPngsDecodeIdentically) {
  const cv::Mat img = testImage(120, 161, 7);
  for (const int level : {0, 1, 9}) {
    Bytes png;
    ASSERT_TRUE(cv::imencode(".png", img, png, {cv::IMWRITE_PNG_COMPRESSION, level}));
    cv::Mat ours;
    ASSERT_TRUE(iraf_vo::decodeGray8Png(png.data(), png.size(), &ours)) << "level " << level;
    EXPECT_TRUE(sameImage(ours, img)) << "level " << level;
  }
}

TEST(PngGray8, OtherPngsAreLeftToOpenCv) {
  const cv::Mat img = testImage(16, 24, 3);
  cv::Mat out;
  Bytes png16, color;
  cv::Mat img16;
  img.convertTo(img16, CV_16U, 257.0);
  ASSERT_TRUE(cv::imencode(".png", img16, png16));
  cv::Mat bgr;
  cv::merge(std::vector<cv::Mat>{img, img, img}, bgr);
  ASSERT_TRUE(cv::imencode(".png", bgr, color));
  EXPECT_FALSE(iraf_vo::decodeGray8Png(png16.data(), png16.size(), &out));
  EXPECT_FALSE(iraf_vo::decodeGray8Png(color.data(), color.size(), &out));
  EXPECT_TRUE(out.empty());
  // decodeImage falls back to OpenCV for them: same result as cv::imdecode.
  EXPECT_TRUE(sameImage(iraf_vo::decodeImage(png16.data(), png16.size()), openCvDecode(png16)));
  EXPECT_TRUE(sameImage(iraf_vo::decodeImage(color.data(), color.size()), openCvDecode(color)));
  PngOptions trns;
  trns.extra_chunk = "tRNS";  // transparency may make OpenCV return an alpha channel
  const Bytes with_trns = encodeGrayPng(img, trns);
  EXPECT_FALSE(iraf_vo::decodeGray8Png(with_trns.data(), with_trns.size(), &out));
  PngOptions interlaced;
  interlaced.interlace = 1;
  const Bytes adam7 = encodeGrayPng(img, interlaced);
  EXPECT_FALSE(iraf_vo::decodeGray8Png(adam7.data(), adam7.size(), &out));
  const Bytes jpeg_like{0xff, 0xd8, 0xff, 0xe0, 0, 0, 0, 0};
  EXPECT_FALSE(iraf_vo::decodeGray8Png(jpeg_like.data(), jpeg_like.size(), &out));
  EXPECT_FALSE(iraf_vo::decodeGray8Png(nullptr, 0, &out));
}

// Any damage (bit flips with or without a repaired CRC, truncation): the fast path either declines, or decodes
// exactly what OpenCV decodes. It never returns different pixels and never reads out of bounds (ASan stage).
TEST(PngGray8, DamagedFilesNeverDecodeDifferently) {
  const cv::Mat img = testImage(40, 57, 11);
  PngOptions o;
  o.idat_bytes = 300;
  o.text_chunks = true;  // damage in a tEXt chunk (not CRC-checked: libpng only warns there) still decodes
  const Bytes good = encodeGrayPng(img, o);
  std::mt19937 rng(5);
  int declined = 0, decoded = 0;
  for (int trial = 0; trial < 600; ++trial) {
    Bytes bad = good;
    if (trial % 3 == 0) {
      bad.resize(std::uniform_int_distribution<size_t>(0, good.size() - 1)(rng));
    } else {
      const size_t at = std::uniform_int_distribution<size_t>(0, good.size() - 1)(rng);
      bad[at] ^= static_cast<uint8_t>(1 + rng() % 255);
      if (trial % 3 == 2) {  // repair the CRC of the chunk that was hit, so the zlib stream itself is damaged
        size_t pos = 8;
        while (pos + 12 <= bad.size()) {
          const uint32_t len = (uint32_t(bad[pos]) << 24) | (uint32_t(bad[pos + 1]) << 16) |
                               (uint32_t(bad[pos + 2]) << 8) | bad[pos + 3];
          if (len > bad.size() || pos + 12 + len > bad.size()) break;
          if (at >= pos + 4 && at < pos + 8 + len) {
            const uint32_t crc = libdeflate_crc32(0, &bad[pos + 4], len + 4);
            for (int k = 0; k < 4; ++k) bad[pos + 8 + len + k] = static_cast<uint8_t>(crc >> (24 - 8 * k));
            break;
          }
          pos += 12 + len;
        }
      }
    }
    cv::Mat ours;
    if (!iraf_vo::decodeGray8Png(bad.data(), bad.size(), &ours)) {
      ++declined;
      continue;
    }
    ++decoded;
    EXPECT_TRUE(sameImage(ours, openCvDecode(bad))) << "trial " << trial;
  }
  EXPECT_GT(declined, 300);  // the damage was noticed
  EXPECT_GT(decoded, 0);     // e.g. flips inside the tEXt chunks' text
}

TEST(PngGray8, SharedEurocFramesDecodeLikeImread) {
  const std::string dir = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " not present (shared data absent)";
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".png") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 30u);
  for (size_t i = 0; i < files.size(); i += files.size() / 30) {
    Bytes bytes;
    ASSERT_TRUE(iraf_vo::readFileBytes(files[i], &bytes)) << files[i];
    cv::Mat ours;
    ASSERT_TRUE(iraf_vo::decodeGray8Png(bytes.data(), bytes.size(), &ours)) << files[i];
    EXPECT_TRUE(sameImage(ours, cv::imread(files[i], cv::IMREAD_UNCHANGED))) << files[i];
    cv::Mat via_reader;
    std::string err;
    ASSERT_TRUE(iraf_vo::readMono8(files[i], &via_reader, &err)) << err;
    EXPECT_TRUE(sameImage(via_reader, ours)) << files[i];
  }
}
