#pragma once
// Image files written and read by the tools and tests: OpenEXR for linear HDR data (renders, references, debug
// images), PNG for tonemapped 8-bit output (SPEC §2: linear float before tonemapping, sRGB only for PNG output).
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <vector>

namespace ssvgi::renderer {

// A failed image read or write. what() is one line: the file, then the problem.
class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A float image. Pixels are stored row by row from the top row down, each pixel's channels interleaved:
// the value of channel c at column x, row y is pixels[(y * width + x) * channels + c].
struct FloatImage {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t channels = 0;  // 1 (stored as EXR channel Y), 3 (R, G, B) or 4 (R, G, B, A)
  std::vector<float> pixels;
};

// Writes 32-bit float channels (never half: a reference image must not lose precision), ZIP-compressed (lossless).
// Throws ImageIoError if the image is malformed or the file cannot be written.
void writeExr(const std::filesystem::path& path, const FloatImage& image);

// Reads a single-part scanline EXR with channels Y, RGB or RGBA (half or float; returned as float).
// Throws ImageIoError if the file is missing, not an EXR, corrupt or holds other channels.
FloatImage readExr(const std::filesystem::path& path);

// Writes an 8-bit RGBA PNG from width * height * 4 bytes, rows top to bottom, colour already encoded (e.g. sRGB).
// Throws ImageIoError if the pixel data has the wrong size or the file cannot be written.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba);

}  // namespace ssvgi::renderer
