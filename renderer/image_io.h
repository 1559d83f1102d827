#pragma once
// Image files written and read by the tools and tests: OpenEXR for linear HDR data (renders, references, debug
// images), PNG for tonemapped 8-bit output (SPEC §2: linear float before tonemapping, sRGB only for PNG output). With
// them, what every file the tools read or write goes through: reads of regular files of a bounded size only, and
// writes that replace a file whole or not at all.
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ssvgi::renderer {

// A failed file read or write. what() is one line: the file, then the problem.
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

// The most readExr reads: an EXR file of up to 1 GiB holding up to 8192 × 8192 pixels (1 GiB as RGBA float). Bounds
// against a corrupt header or a device file, far above anything the tools write.
inline constexpr uint64_t kMaxExrFileBytes = uint64_t{1} << 30;
inline constexpr uint64_t kMaxExrPixels = uint64_t{8192} * 8192;

// Writes 32-bit float channels (never half: a reference image must not lose precision), ZIP-compressed (lossless), as
// StagedFiles does: an existing file is replaced whole or not at all.
// Throws ImageIoError if the image is malformed or the file cannot be written.
void writeExr(const std::filesystem::path& path, const FloatImage& image);

// Reads a single-part scanline EXR with channels Y, RGB or RGBA (half or float; returned as float). The values are
// returned as stored, NaN and infinities included.
// Throws ImageIoError if the file is missing, not a regular file, larger than kMaxExrFileBytes or kMaxExrPixels, not
// an EXR, corrupt or holds other channels.
FloatImage readExr(const std::filesystem::path& path);

// Writes an 8-bit RGBA PNG from width * height * 4 bytes, rows top to bottom, colour already encoded (e.g. sRGB), as
// StagedFiles does.
// Throws ImageIoError if the pixel data has the wrong size or the file cannot be written.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba);

// The bytes of the file at `path`. Throws ImageIoError naming the file when it is missing, is not a regular file (a
// folder, or a device such as /dev/zero, whose reading would never end), holds more than `maxBytes` or cannot be read.
std::vector<uint8_t> readFileBytes(const std::filesystem::path& path, uint64_t maxBytes);

// Files that are replaced together or not at all, such as the images and stats.json of one render. Each is written under
// a temporary name beside its destination (DESTINATION.partial-PID); commit() renames them into place once every one
// has been written. An error half-way, or a process killed before commit(), leaves every destination as it was (a
// killed process also leaves its .partial files); a StagedFiles destroyed before commit() removes its temporary files.
// Each rename replaces its destination atomically, so no destination is ever seen truncated.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();

  // Each throws ImageIoError naming `destination` when the data is malformed (the images) or cannot be written.
  void writeExr(const std::filesystem::path& destination, const FloatImage& image);
  void writePng(const std::filesystem::path& destination, uint32_t width, uint32_t height,
                std::span<const uint8_t> rgba);
  void writeBytes(const std::filesystem::path& destination, std::span<const uint8_t> bytes);
  void writeText(const std::filesystem::path& destination, std::string_view text);

  // Renames every staged file into place. Throws ImageIoError naming the destination, before renaming any, when one
  // of the destinations is a folder; a rename that fails after that (the file system failing) leaves the files
  // renamed before it in place.
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // (temporary, destination)
};

}  // namespace ssvgi::renderer
