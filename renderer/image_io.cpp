#include "image_io.h"

#include <stb/stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

#include <unistd.h>

namespace ssvgi::renderer {

namespace {

ImageIoError fileError(const std::filesystem::path& path, std::string_view problem) {
  return ImageIoError(path.string() + ": " + std::string(problem));
}

// The files are read and written here rather than by tinyexr and stb, so that every failure to open a file is
// reported alike, with the operating system's reason.
void writeFile(const std::filesystem::path& path, const std::filesystem::path& nameInErrors,
               std::span<const uint8_t> bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) {
    throw fileError(nameInErrors, std::string("cannot open for writing: ") + std::strerror(errno));
  }
  if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size()) {
    const int reason = errno;
    std::fclose(file);
    throw fileError(nameInErrors, std::string("cannot write: ") + std::strerror(reason));
  }
  if (std::fclose(file) != 0) {
    throw fileError(nameInErrors, std::string("cannot write: ") + std::strerror(errno));
  }
}

// tinyexr's error messages are allocated by tinyexr and may span lines; returns one line and frees the original.
std::string takeExrMessage(const char* message) {
  if (message == nullptr) {
    return "no reason given";
  }
  std::string text = message;
  FreeEXRErrorMessage(message);
  std::replace(text.begin(), text.end(), '\n', ' ');
  text.erase(text.find_last_not_of(' ') + 1);
  return text;
}

// EXR channel names in FloatImage's interleaved order, for 1, 3 and 4 channels.
std::span<const char* const> exrChannelNames(uint32_t channelCount) {
  static constexpr std::array<const char*, 1> kGrey{"Y"};
  static constexpr std::array<const char*, 3> kRgb{"R", "G", "B"};
  static constexpr std::array<const char*, 4> kRgba{"R", "G", "B", "A"};
  switch (channelCount) {
    case 1:
      return kGrey;
    case 3:
      return kRgb;
    case 4:
      return kRgba;
    default:
      return {};
  }
}

struct ExrHeader {
  EXRHeader value;
  ExrHeader() { InitEXRHeader(&value); }
  ~ExrHeader() { FreeEXRHeader(&value); }
  ExrHeader(const ExrHeader&) = delete;
  ExrHeader& operator=(const ExrHeader&) = delete;
};

struct ExrImage {
  EXRImage value;
  ExrImage() { InitEXRImage(&value); }
  ~ExrImage() { FreeEXRImage(&value); }
  ExrImage(const ExrImage&) = delete;
  ExrImage& operator=(const ExrImage&) = delete;
};

std::vector<uint8_t> encodeExr(const std::filesystem::path& path, const FloatImage& image) {
  const std::span<const char* const> names = exrChannelNames(image.channels);
  if (names.empty()) {
    throw fileError(path, "cannot write an EXR with " + std::to_string(image.channels) +
                              " channels (expected 1, 3 or 4)");
  }
  if (image.width == 0 || image.height == 0 || image.width > INT_MAX || image.height > INT_MAX) {
    throw fileError(path, "cannot write an EXR of " + std::to_string(image.width) + "x" +
                              std::to_string(image.height) + " pixels");
  }
  const size_t pixelCount = size_t{image.width} * image.height;
  if (image.pixels.size() != pixelCount * image.channels) {
    throw fileError(path, "the image holds " + std::to_string(image.pixels.size()) + " values, expected " +
                              std::to_string(pixelCount * image.channels));
  }

  // OpenEXR lists channels sorted by name (A, B, G, R); readers match them by name, not by position.
  std::vector<uint32_t> interleavedIndexOfFileChannel(image.channels);
  for (uint32_t channel = 0; channel < image.channels; ++channel) {
    interleavedIndexOfFileChannel[channel] = channel;
  }
  std::sort(interleavedIndexOfFileChannel.begin(), interleavedIndexOfFileChannel.end(),
            [&names](uint32_t a, uint32_t b) { return std::strcmp(names[a], names[b]) < 0; });

  std::vector<EXRChannelInfo> channelInfos(image.channels);
  std::vector<int> pixelTypes(image.channels, TINYEXR_PIXELTYPE_FLOAT);
  std::vector<std::vector<float>> planes(image.channels, std::vector<float>(pixelCount));
  std::vector<uint8_t*> planePointers(image.channels);
  for (uint32_t fileChannel = 0; fileChannel < image.channels; ++fileChannel) {
    const uint32_t interleavedIndex = interleavedIndexOfFileChannel[fileChannel];
    std::strncpy(channelInfos[fileChannel].name, names[interleavedIndex], sizeof(channelInfos[fileChannel].name) - 1);
    for (size_t pixel = 0; pixel < pixelCount; ++pixel) {
      planes[fileChannel][pixel] = image.pixels[pixel * image.channels + interleavedIndex];
    }
    planePointers[fileChannel] = reinterpret_cast<uint8_t*>(planes[fileChannel].data());
  }

  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(image.channels);
  header.channels = channelInfos.data();
  header.pixel_types = pixelTypes.data();
  header.requested_pixel_types = pixelTypes.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  EXRImage exrImage;
  InitEXRImage(&exrImage);
  exrImage.num_channels = static_cast<int>(image.channels);
  exrImage.width = static_cast<int>(image.width);
  exrImage.height = static_cast<int>(image.height);
  exrImage.images = planePointers.data();

  uint8_t* encoded = nullptr;
  const char* message = nullptr;
  const size_t encodedSize = SaveEXRImageToMemory(&exrImage, &header, &encoded, &message);
  const std::unique_ptr<uint8_t, decltype(&std::free)> encodedOwner(encoded, &std::free);
  if (encodedSize == 0) {
    throw fileError(path, "cannot encode EXR: " + takeExrMessage(message));
  }
  return {encoded, encoded + encodedSize};
}

std::vector<uint8_t> encodePng(const std::filesystem::path& path, uint32_t width, uint32_t height,
                               std::span<const uint8_t> rgba) {
  constexpr uint32_t kBytesPerPixel = 4;
  if (width == 0 || height == 0 || width > INT_MAX / kBytesPerPixel || height > INT_MAX) {
    throw fileError(path, "cannot write a PNG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  const size_t expectedSize = size_t{width} * height * kBytesPerPixel;
  if (rgba.size() != expectedSize) {
    throw fileError(path, "the image holds " + std::to_string(rgba.size()) + " bytes, expected " +
                              std::to_string(expectedSize));
  }
  std::vector<uint8_t> encoded;
  const auto appendToEncoded = [](void* context, void* data, int size) {
    auto& output = *static_cast<std::vector<uint8_t>*>(context);
    const auto* bytes = static_cast<const uint8_t*>(data);
    output.insert(output.end(), bytes, bytes + size);
  };
  if (stbi_write_png_to_func(appendToEncoded, &encoded, static_cast<int>(width), static_cast<int>(height),
                             static_cast<int>(kBytesPerPixel), rgba.data(),
                             static_cast<int>(width * kBytesPerPixel)) == 0) {
    throw fileError(path, "cannot encode PNG");
  }
  return encoded;
}

}  // namespace

void writeExr(const std::filesystem::path& path, const FloatImage& image) {
  StagedFiles files;
  files.writeExr(path, image);
  files.commit();
}

FloatImage readExr(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path, kMaxExrFileBytes);

  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) {
    throw fileError(path, "not an OpenEXR file");
  }
  if (version.multipart != 0 || version.non_image != 0) {
    throw fileError(path, "multi-part and deep EXR files are not supported");
  }
  ExrHeader header;
  const char* message = nullptr;
  if (ParseEXRHeaderFromMemory(&header.value, &version, bytes.data(), bytes.size(), &message) != TINYEXR_SUCCESS) {
    throw fileError(path, "corrupt EXR header: " + takeExrMessage(message));
  }
  if (header.value.tiled != 0) {
    throw fileError(path, "tiled EXR files are not supported");
  }
  // Checked before tinyexr allocates the image: a few bytes of header can claim millions of pixels.
  const EXRBox2i& window = header.value.data_window;
  const int64_t width = int64_t{window.max_x} - window.min_x + 1;
  const int64_t height = int64_t{window.max_y} - window.min_y + 1;
  if (width <= 0 || height <= 0 || static_cast<uint64_t>(width) * static_cast<uint64_t>(height) > kMaxExrPixels) {
    throw fileError(path, "corrupt EXR header: a data window of " + std::to_string(width) + "x" +
                              std::to_string(height) + " pixels (at most " + std::to_string(kMaxExrPixels) +
                              " are read)");
  }

  const auto channelCount = static_cast<uint32_t>(header.value.num_channels);
  const std::span<const char* const> names = exrChannelNames(channelCount);
  if (names.empty()) {
    throw fileError(path, "unsupported channel count " + std::to_string(header.value.num_channels) +
                              " (expected 1, 3 or 4)");
  }
  // Each file channel must name a different one of the expected channels.
  std::vector<uint32_t> interleavedIndexOfFileChannel(channelCount);
  std::string fileChannelNames;
  uint32_t matchedChannels = 0;  // bit i: interleaved channel i was found
  for (uint32_t fileChannel = 0; fileChannel < channelCount; ++fileChannel) {
    const char* name = header.value.channels[fileChannel].name;
    if (fileChannel != 0) fileChannelNames += ' ';
    fileChannelNames += name;
    const auto match = std::find_if(names.begin(), names.end(),
                                    [name](const char* expected) { return std::strcmp(expected, name) == 0; });
    if (match != names.end()) {
      interleavedIndexOfFileChannel[fileChannel] = static_cast<uint32_t>(match - names.begin());
      matchedChannels |= 1u << interleavedIndexOfFileChannel[fileChannel];
    }
  }
  if (matchedChannels != (1u << channelCount) - 1u) {
    throw fileError(path, "unsupported channels '" + fileChannelNames + "' (expected Y, R G B or R G B A)");
  }
  for (uint32_t fileChannel = 0; fileChannel < channelCount; ++fileChannel) {
    if (header.value.pixel_types[fileChannel] == TINYEXR_PIXELTYPE_UINT) {
      throw fileError(path, "unsupported pixel type uint in channel " +
                                std::string(header.value.channels[fileChannel].name));
    }
    header.value.requested_pixel_types[fileChannel] = TINYEXR_PIXELTYPE_FLOAT;  // tinyexr widens half to float
  }

  ExrImage exrImage;
  // tinyexr (1.0.1) sets num_channels only once it has decoded the pixels, but on a failure to decode them it calls
  // FreeEXRImage itself, which frees only the first num_channels planes; set beforehand, it frees them all.
  exrImage.value.num_channels = header.value.num_channels;
  if (LoadEXRImageFromMemory(&exrImage.value, &header.value, bytes.data(), bytes.size(), &message) !=
      TINYEXR_SUCCESS) {
    // What tinyexr freed it left pointed to: forget it, or ExrImage's destructor frees it a second time.
    InitEXRImage(&exrImage.value);
    throw fileError(path, "corrupt EXR data: " + takeExrMessage(message));
  }
  if (exrImage.value.images == nullptr || exrImage.value.width != width || exrImage.value.height != height) {
    throw fileError(path, "corrupt EXR data: the pixels do not match the header's data window");
  }

  FloatImage image{.width = static_cast<uint32_t>(width), .height = static_cast<uint32_t>(height),
                   .channels = channelCount};
  const size_t pixelCount = size_t{image.width} * image.height;
  image.pixels.resize(pixelCount * channelCount);
  for (uint32_t fileChannel = 0; fileChannel < channelCount; ++fileChannel) {
    const auto* plane = reinterpret_cast<const float*>(exrImage.value.images[fileChannel]);
    const uint32_t interleavedIndex = interleavedIndexOfFileChannel[fileChannel];
    for (size_t pixel = 0; pixel < pixelCount; ++pixel) {
      image.pixels[pixel * channelCount + interleavedIndex] = plane[pixel];
    }
  }
  return image;
}

void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba) {
  StagedFiles files;
  files.writePng(path, width, height, rgba);
  files.commit();
}

std::vector<uint8_t> readFileBytes(const std::filesystem::path& path, uint64_t maxBytes) {
  // Looked at before opening: opening a named pipe waits for a writer, and reading a device may never end.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error) {
    throw fileError(path, "cannot open for reading: " + error.message());
  }
  if (status.type() == std::filesystem::file_type::directory) {
    throw fileError(path, "is a folder, not a file");
  }
  if (status.type() != std::filesystem::file_type::regular) {
    throw fileError(path, "is not a regular file (a device, pipe or socket)");
  }
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (error) {
    throw fileError(path, "cannot read: " + error.message());
  }
  const auto tooLarge = [&](uintmax_t bytes) {
    return fileError(path, "holds " + std::to_string(bytes) + " bytes, more than the " + std::to_string(maxBytes) +
                               " read at most");
  };
  if (size > maxBytes) {
    throw tooLarge(size);
  }

  std::unique_ptr<std::FILE, decltype(&std::fclose)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (file == nullptr) {
    throw fileError(path, std::string("cannot open for reading: ") + std::strerror(errno));
  }
  std::vector<uint8_t> bytes;
  bytes.reserve(size);
  std::array<uint8_t, 1 << 16> chunk;
  size_t count = 0;
  while ((count = std::fread(chunk.data(), 1, chunk.size(), file.get())) > 0) {
    bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(count));
    if (bytes.size() > maxBytes) {
      throw tooLarge(bytes.size());  // it grew while being read
    }
  }
  if (std::ferror(file.get()) != 0) {
    throw fileError(path, std::string("cannot read: ") + std::strerror(errno));
  }
  return bytes;
}

StagedFiles::~StagedFiles() {
  for (const auto& [temporary, destination] : staged_) {
    std::error_code ignored;  // already renamed into place, or never created
    std::filesystem::remove(temporary, ignored);
  }
}

void StagedFiles::writeExr(const std::filesystem::path& destination, const FloatImage& image) {
  writeBytes(destination, encodeExr(destination, image));
}

void StagedFiles::writePng(const std::filesystem::path& destination, uint32_t width, uint32_t height,
                           std::span<const uint8_t> rgba) {
  writeBytes(destination, encodePng(destination, width, height, rgba));
}

void StagedFiles::writeText(const std::filesystem::path& destination, std::string_view text) {
  writeBytes(destination, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
}

void StagedFiles::writeBytes(const std::filesystem::path& destination, std::span<const uint8_t> bytes) {
  for (const auto& staged : staged_) {
    if (staged.second == destination) {
      throw fileError(destination, "written twice in one set of files");
    }
  }
  std::filesystem::path temporary = destination;
  temporary += ".partial-" + std::to_string(getpid());
  staged_.emplace_back(temporary, destination);  // listed first, so that a half-written file is removed too
  writeFile(temporary, destination, bytes);
}

void StagedFiles::commit() {
  // rename() cannot replace a folder with a file; finding that out half-way would leave some files new, some old.
  for (const auto& [temporary, destination] : staged_) {
    std::error_code error;
    if (std::filesystem::is_directory(destination, error)) {
      throw fileError(destination, "is a folder; cannot replace it with a file");
    }
  }
  for (const auto& [temporary, destination] : staged_) {
    std::error_code error;
    std::filesystem::rename(temporary, destination, error);
    if (error) {
      throw fileError(destination, "cannot move " + temporary.filename().string() + " into place: " + error.message());
    }
  }
  staged_.clear();
}

}  // namespace ssvgi::renderer
