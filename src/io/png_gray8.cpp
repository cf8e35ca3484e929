#include "iraf_vo/io/png_gray8.h"

#include <libdeflate.h>

#include <algorithm>
#include <climits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>  // IMREAD_* flags (the codecs themselves: image_codecs.h)

#include "iraf_vo/io/image_codecs.h"

namespace iraf_vo {

namespace {

constexpr uint8_t kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
constexpr uint64_t kMaxRawBytes = uint64_t(1) << 30;  // larger images go to OpenCV

uint32_t readBigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

bool chunkIs(const uint8_t* type, const char* name) { return std::memcmp(type, name, 4) == 0; }

// Chunks that do not change what OpenCV decodes for an 8-bit grayscale image.
bool isMetadataChunk(const uint8_t* type) {
  return chunkIs(type, "tEXt") || chunkIs(type, "zTXt") || chunkIs(type, "iTXt") || chunkIs(type, "tIME") ||
         chunkIs(type, "pHYs");
}

// One decompressor and the scratch buffers per thread (no per-frame allocation once warm).
struct DecoderState {
  libdeflate_decompressor* inflater = libdeflate_alloc_decompressor();
  std::vector<uint8_t> compressed, filtered, zero_row, block_rows;  // block_rows: the SIMD front's output
  ~DecoderState() {
    if (inflater) libdeflate_free_decompressor(inflater);
  }
};

DecoderState& decoderState() {
  thread_local DecoderState state;
  return state;
}

// PNG filter types (PNG spec, section 9) for one byte per pixel: x = filtered byte + predictor, with
// a = left, b = above, c = above-left of the reconstructed image (0 outside it).
void unfilterSub(const uint8_t* f, uint8_t* x, int w) {
  uint8_t a = 0;
  for (int i = 0; i < w; ++i) x[i] = a = static_cast<uint8_t>(f[i] + a);
}

void unfilterUp(const uint8_t* f, const uint8_t* b, uint8_t* x, int w) {
  for (int i = 0; i < w; ++i) x[i] = static_cast<uint8_t>(f[i] + b[i]);
}

void unfilterAverage(const uint8_t* f, const uint8_t* b, uint8_t* x, int w) {
  int a = 0;
  for (int i = 0; i < w; ++i) {
    a = (f[i] + ((a + b[i]) >> 1)) & 0xff;
    x[i] = static_cast<uint8_t>(a);
  }
}

// One Paeth pixel, branch-free (libpng's per-pixel branches mispredict on camera images). a / c: the row's
// left and above-left values, updated for the next pixel.
inline void paethPixel(uint8_t f, int b, uint8_t* x, int* a, int* c) {
  const int pa = std::abs(b - *c), pb = std::abs(*a - *c), pc = std::abs(*a + b - 2 * *c);
  const int below = pb <= pc ? b : *c;
  const int pred = (pa <= pb && pa <= pc) ? *a : below;
  *a = (f + pred) & 0xff;
  *x = static_cast<uint8_t>(*a);
  *c = b;
}

void unfilterPaeth(const uint8_t* f, const uint8_t* b, uint8_t* x, int w) {
  int a = 0, c = 0;
  for (int i = 0; i < w; ++i) paethPixel(f[i], b[i], &x[i], &a, &c);
}

// kRows consecutive Paeth rows at once on a skewed front (row k one pixel behind row k - 1, whose pixel i it
// needs as b and c): each row is a serial chain through a, and kRows independent chains keep the CPU busy.
// Same pixels as unfilterPaeth row by row.
constexpr int kRows = 4;
void unfilterPaethRows(const uint8_t* const* f, const uint8_t* above, uint8_t* const* x, int w) {
  int a[kRows] = {0}, c[kRows] = {0};
  auto pixel = [&](int k, int i) { paethPixel(f[k][i], k ? x[k - 1][i] : above[i], &x[k][i], &a[k], &c[k]); };
  for (int t = 0; t < kRows - 1; ++t)  // the front enters: row k starts at step k
    for (int k = 0; k <= t; ++k) pixel(k, t - k);
  for (int t = kRows - 1; t < w; ++t)
    for (int k = 0; k < kRows; ++k) pixel(k, t - k);
  for (int t = w; t < w + kRows - 1; ++t)  // and leaves: row k ends at step w - 1 + k
    for (int k = t - w + 1; k < kRows; ++k) pixel(k, t - k);
}

#if defined(__SSE2__)
// 16 rows at once, one row per byte lane, on the same skewed front (lane k = row r + k at column s - k):
// each step reconstructs one pixel of every row, with a = the lane's previous result, b / c = the lane
// above's previous / second-previous result (lane 0: the row above the block). Every filter type per lane
// (PNG spec 9.2-9.4; the Paeth choice with |p - a| = |b - c|, |p - b| = |a - c|, |p - c| = their sum or
// difference by sign). Rows go in and out through 16 x 16 byte transposes. Same pixels as unfilterRows'
// scalar paths. `f` = filtered bytes of row r (after its filter-type byte), rows `stride` apart; row r + k is
// read from 15 bytes before its start (inside row r + k - 1) to 15 bytes past the block's last row (the
// buffer has 32 bytes of slack); `above` is read to above[w + 29] (a zero row of w + 32 bytes, or an image row
// followed by >= 16 more rows of the same contiguous image); `out` rows of w + 48 bytes, pixel 0 at out + 16
// (scratch the caller copies from).
inline __m128i absDiffU8(__m128i x, __m128i y) { return _mm_or_si128(_mm_subs_epu8(x, y), _mm_subs_epu8(y, x)); }
inline __m128i lessEqualU8(__m128i x, __m128i y) { return _mm_cmpeq_epi8(_mm_min_epu8(x, y), x); }
inline __m128i select(__m128i m, __m128i x, __m128i y) { return _mm_or_si128(_mm_and_si128(m, x), _mm_andnot_si128(m, y)); }

void transpose16(__m128i* v) {  // v[i] byte j <- v[j] byte i: four rounds of interleaving rows i and i + 8
  __m128i t[16];
  for (int round = 0; round < 4; ++round) {
    for (int i = 0; i < 8; ++i) {
      t[2 * i] = _mm_unpacklo_epi8(v[i], v[i + 8]);
      t[2 * i + 1] = _mm_unpackhi_epi8(v[i], v[i + 8]);
    }
    for (int i = 0; i < 16; ++i) v[i] = t[i];
  }
}

void unfilterBlock16(const uint8_t* f, size_t stride, const uint8_t* types, const uint8_t* above, int w, uint8_t* out,
                     size_t out_stride) {
  uint8_t lane_type[5][16];
  for (int t = 0; t < 5; ++t)
    for (int k = 0; k < 16; ++k) lane_type[t][k] = types[k] == t ? 0xff : 0;
  const __m128i is_sub = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lane_type[1]));
  const __m128i is_up = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lane_type[2]));
  const __m128i is_avg = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lane_type[3]));
  const __m128i is_paeth = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lane_type[4]));
  const __m128i lane0 = _mm_cvtsi32_si128(0xff), one = _mm_set1_epi8(1);
  __m128i p1 = _mm_setzero_si128(), p2 = _mm_setzero_si128();  // the front's last two steps
  for (int c0 = 0; c0 < w + 15; c0 += 16) {
    __m128i v[16];
    for (int k = 0; k < 16; ++k)  // row r + k from column c0 - k: after the transpose v[j] is step c0 + j
      v[k] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(f + k * stride + c0 - k));
    transpose16(v);
    __m128i up = _mm_loadu_si128(reinterpret_cast<const __m128i*>(above + c0));  // lane 0's b, step by step
    __m128i up_left = c0 > 0 ? _mm_loadu_si128(reinterpret_cast<const __m128i*>(above + c0 - 1))
                             : _mm_slli_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(above)), 1);
    for (int j = 0; j < 16; ++j) {
      const __m128i a = p1;
      const __m128i b = _mm_or_si128(_mm_slli_si128(p1, 1), _mm_and_si128(up, lane0));
      const __m128i c = _mm_or_si128(_mm_slli_si128(p2, 1), _mm_and_si128(up_left, lane0));
      up = _mm_srli_si128(up, 1);
      up_left = _mm_srli_si128(up_left, 1);
      const __m128i pa = absDiffU8(b, c), pb = absDiffU8(a, c);
      const __m128i same_sign = _mm_cmpeq_epi8(_mm_cmpeq_epi8(_mm_max_epu8(a, c), a), _mm_cmpeq_epi8(_mm_max_epu8(b, c), b));
      const __m128i pc = select(same_sign, _mm_adds_epu8(pa, pb), absDiffU8(pa, pb));
      const __m128i take_a = _mm_and_si128(lessEqualU8(pa, pb), lessEqualU8(pa, pc));
      const __m128i paeth = select(take_a, a, select(lessEqualU8(pb, pc), b, c));
      const __m128i avg = _mm_sub_epi8(_mm_avg_epu8(a, b), _mm_and_si128(_mm_xor_si128(a, b), one));
      const __m128i pred = _mm_or_si128(_mm_or_si128(_mm_and_si128(is_paeth, paeth), _mm_and_si128(is_sub, a)),
                                        _mm_or_si128(_mm_and_si128(is_up, b), _mm_and_si128(is_avg, avg)));
      __m128i x = _mm_add_epi8(v[j], pred);
      if (c0 == 0) {  // lanes k > j are left of column 0: 0, so row k starts with a = c = 0
        const __m128i started = _mm_cmpgt_epi8(_mm_set1_epi8(static_cast<char>(j + 1)), _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
        x = _mm_and_si128(x, started);
      }
      p2 = p1;
      p1 = x;
      v[j] = x;
    }
    transpose16(v);  // v[k]: row r + k, columns c0 - k .. c0 - k + 15
    for (int k = 0; k < 16; ++k) _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k * out_stride + 16 + c0 - k), v[k]);
  }
}
#endif

// The scalar paths for rows [first, last): 4-row Paeth fronts where 4 Paeth rows follow, else row by row.
bool unfilterRowRange(const std::vector<uint8_t>& filtered, const uint8_t* zero_row, cv::Mat* img, int first, int last) {
  const int w = img->cols;
  auto filterType = [&](int r) { return filtered[static_cast<size_t>(r) * (w + 1)]; };
  for (int r = first; r < last;) {
    const uint8_t* f = filtered.data() + static_cast<size_t>(r) * (w + 1) + 1;
    const uint8_t* above = r > 0 ? img->ptr<uint8_t>(r - 1) : zero_row;
    uint8_t* x = img->ptr<uint8_t>(r);
    bool paeth_block = w >= kRows && r + kRows <= last;
    for (int k = 0; paeth_block && k < kRows; ++k) paeth_block = filterType(r + k) == 4;
    if (paeth_block) {
      const uint8_t* fs[kRows];
      uint8_t* xs[kRows];
      for (int k = 0; k < kRows; ++k) {
        fs[k] = f + static_cast<size_t>(k) * (w + 1);
        xs[k] = img->ptr<uint8_t>(r + k);
      }
      unfilterPaethRows(fs, above, xs, w);
      r += kRows;
      continue;
    }
    switch (filterType(r)) {
      case 0: std::memcpy(x, f, w); break;
      case 1: unfilterSub(f, x, w); break;
      case 2: unfilterUp(f, above, x, w); break;
      case 3: unfilterAverage(f, above, x, w); break;
      case 4: unfilterPaeth(f, above, x, w); break;
      default: return false;
    }
    ++r;
  }
  return true;
}

bool unfilterRows(const std::vector<uint8_t>& filtered, const uint8_t* zero_row, std::vector<uint8_t>* scratch,
                  cv::Mat* img) {
  const int w = img->cols, rows = img->rows;
  for (int r = 0; r < rows; ++r)
    if (filtered[static_cast<size_t>(r) * (w + 1)] > 4) return false;  // filter types 0-4 only
  int r = 0;
#if defined(__SSE2__)
  // Blocks of 16 rows through the SIMD front; the rest (< 16 rows) on the scalar paths.
  const size_t out_stride = static_cast<size_t>(w) + 48;
  scratch->resize(16 * out_stride);
  for (; r + 16 <= rows; r += 16) {
    uint8_t types[16];
    for (int k = 0; k < 16; ++k) types[k] = filtered[static_cast<size_t>(r + k) * (w + 1)];
    unfilterBlock16(filtered.data() + static_cast<size_t>(r) * (w + 1) + 1, w + 1, types,
                    r > 0 ? img->ptr<uint8_t>(r - 1) : zero_row, w, scratch->data(), out_stride);
    for (int k = 0; k < 16; ++k) std::memcpy(img->ptr<uint8_t>(r + k), scratch->data() + k * out_stride + 16, w);
  }
#else
  (void)scratch;
#endif
  return unfilterRowRange(filtered, zero_row, img, r, rows);
}

}  // namespace

bool decodeGray8Png(const uint8_t* data, size_t size, cv::Mat* out) {
  if (!data || size < 8 + 25 || std::memcmp(data, kSignature, 8) != 0) return false;
  DecoderState& st = decoderState();
  if (!st.inflater) return false;
  st.compressed.clear();
  int width = 0, height = 0;
  bool have_header = false, idat_done = false, have_end = false;
  size_t pos = 8;
  while (!have_end) {
    if (size - pos < 12) return false;  // truncated
    const uint32_t len = readBigEndian32(data + pos);
    const uint8_t* type = data + pos + 4;
    if (len > 0x7fffffffu || size - pos - 12 < len) return false;
    const uint8_t* body = type + 4;
    const bool critical = chunkIs(type, "IHDR") || chunkIs(type, "IDAT") || chunkIs(type, "IEND");
    if (critical && libdeflate_crc32(0, type, len + 4) != readBigEndian32(body + len)) return false;
    if (!have_header) {
      // IHDR: width, height, bit depth 8, colour type 0 (gray), compression 0, filter 0, interlace 0.
      if (!chunkIs(type, "IHDR") || len != 13) return false;
      const uint32_t w = readBigEndian32(body), h = readBigEndian32(body + 4);
      if (w == 0 || h == 0 || w > INT_MAX || h > INT_MAX) return false;
      if (body[8] != 8 || body[9] != 0 || body[10] != 0 || body[11] != 0 || body[12] != 0) return false;
      if (uint64_t(w + 1) * h > kMaxRawBytes) return false;
      width = static_cast<int>(w);
      height = static_cast<int>(h);
      have_header = true;
    } else if (chunkIs(type, "IDAT")) {
      if (idat_done) return false;  // IDAT chunks must be consecutive
      st.compressed.insert(st.compressed.end(), body, body + len);
    } else if (chunkIs(type, "IEND")) {
      have_end = true;
    } else if (isMetadataChunk(type)) {
      if (!st.compressed.empty()) idat_done = true;
    } else {
      return false;  // palette, transparency, gamma, unknown...: OpenCV decides
    }
    pos += 12 + size_t(len);
  }
  if (st.compressed.empty()) return false;
  const size_t raw_bytes = static_cast<size_t>(width + 1) * height;
  st.filtered.resize(raw_bytes + 32);  // + slack for the SIMD front's reads past the last row
  if (libdeflate_zlib_decompress(st.inflater, st.compressed.data(), st.compressed.size(), st.filtered.data(),
                                 raw_bytes, nullptr) != LIBDEFLATE_SUCCESS)
    return false;  // damaged, too short or too long: OpenCV reports or tolerates it as it does today
  if (st.zero_row.size() < static_cast<size_t>(width) + 32) st.zero_row.assign(static_cast<size_t>(width) + 32, 0);
  cv::Mat img(height, width, CV_8UC1);
  if (!unfilterRows(st.filtered, st.zero_row.data(), &st.block_rows, &img)) return false;
  *out = img;
  return true;
}

cv::Mat decodeImage(const uint8_t* data, size_t size, std::string* error) {
  cv::Mat img;
  if (decodeGray8Png(data, size, &img)) return img;
  if (!data || size == 0 || size > static_cast<size_t>(INT_MAX)) return cv::Mat();
  try {
    img = codecs::imdecode(data, size, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    if (error) *error = e.what();
    return cv::Mat();
  }
  return img;
}

bool readFileBytes(const std::string& path, std::vector<uint8_t>* bytes) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return false;
  const std::streamoff n = in.tellg();
  if (n < 0) return false;
  bytes->resize(static_cast<size_t>(n));
  in.seekg(0);
  return n == 0 || static_cast<bool>(in.read(reinterpret_cast<char*>(bytes->data()), n));
}

}  // namespace iraf_vo
