// EXR and PNG files (renderer/image_io.h): exact round trips, channel naming, and one-line errors naming the file.
#include "image_io.h"

#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <tinyexr.h>

#include <bit>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

namespace ssvgi::renderer {
namespace {

// Each test gets its own fresh directory, so that tests (and other build directories' runs) never share files.
class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (std::filesystem::temp_directory_path() / "ssvgi_image_io_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    directory_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::filesystem::path file(const std::string& name) const { return directory_ / name; }

 private:
  std::filesystem::path directory_;
};

// Values a half-float or a lossy codec would change: negatives, denormals, the extremes of float, signed zero,
// infinities and fractions with a full mantissa.
FloatImage imageWithHardValues(uint32_t channels) {
  const float hardValues[] = {-1.5f,
                              0.1f,
                              -0.0f,
                              std::numeric_limits<float>::denorm_min(),
                              std::numeric_limits<float>::min(),
                              -1e-30f,
                              1e30f,
                              std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::lowest(),
                              std::numeric_limits<float>::infinity(),
                              65504.0f + 1.0f,
                              3.14159274f};
  FloatImage image{.width = 5, .height = 3, .channels = channels};
  image.pixels.resize(size_t{image.width} * image.height * channels);
  for (size_t index = 0; index < image.pixels.size(); ++index) {
    // Mixing in the index makes every value distinct, so that swapped rows or channels show.
    image.pixels[index] = hardValues[index % std::size(hardValues)] * (1.0f + 0x1p-20f * static_cast<float>(index));
  }
  return image;
}

void expectBitIdentical(const FloatImage& actual, const FloatImage& expected) {
  ASSERT_EQ(actual.width, expected.width);
  ASSERT_EQ(actual.height, expected.height);
  ASSERT_EQ(actual.channels, expected.channels);
  ASSERT_EQ(actual.pixels.size(), expected.pixels.size());
  for (size_t index = 0; index < expected.pixels.size(); ++index) {
    EXPECT_EQ(std::bit_cast<uint32_t>(actual.pixels[index]), std::bit_cast<uint32_t>(expected.pixels[index]))
        << "value " << index << ": " << actual.pixels[index] << " instead of " << expected.pixels[index];
  }
}

std::vector<std::string> exrChannelNamesInFile(const std::filesystem::path& path) {
  EXRVersion version;
  EXRHeader header;
  InitEXRHeader(&header);
  const char* message = nullptr;
  EXPECT_EQ(ParseEXRVersionFromFile(&version, path.c_str()), TINYEXR_SUCCESS);
  EXPECT_EQ(ParseEXRHeaderFromFile(&header, &version, path.c_str(), &message), TINYEXR_SUCCESS);
  std::vector<std::string> names;
  for (int channel = 0; channel < header.num_channels; ++channel) {
    names.emplace_back(header.channels[channel].name);
    EXPECT_EQ(header.pixel_types[channel], TINYEXR_PIXELTYPE_FLOAT) << "channel " << names.back();
  }
  FreeEXRHeader(&header);
  return names;
}

// Runs `action`, which must throw ImageIoError, and checks the message: one line that names the file.
template <typename Action>
void expectImageIoErrorNaming(const std::filesystem::path& path, Action action) {
  try {
    action();
    ADD_FAILURE() << "no ImageIoError for " << path;
  } catch (const ImageIoError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST_F(ImageIoTest, exrRoundTripIsBitExactForOneThreeAndFourChannels) {
  for (uint32_t channels : {1u, 3u, 4u}) {
    SCOPED_TRACE("channels " + std::to_string(channels));
    const FloatImage image = imageWithHardValues(channels);
    const std::filesystem::path path = file("image" + std::to_string(channels) + ".exr");
    writeExr(path, image);
    expectBitIdentical(readExr(path), image);
  }
}

TEST_F(ImageIoTest, exrChannelsAreFloatAndNamedYOrRgba) {
  // Names let other tools (OpenEXR viewers, our `compare`) find the channels; OpenEXR lists them sorted by name.
  writeExr(file("y.exr"), imageWithHardValues(1));
  writeExr(file("rgb.exr"), imageWithHardValues(3));
  writeExr(file("rgba.exr"), imageWithHardValues(4));
  EXPECT_EQ(exrChannelNamesInFile(file("y.exr")), (std::vector<std::string>{"Y"}));
  EXPECT_EQ(exrChannelNamesInFile(file("rgb.exr")), (std::vector<std::string>{"B", "G", "R"}));
  EXPECT_EQ(exrChannelNamesInFile(file("rgba.exr")), (std::vector<std::string>{"A", "B", "G", "R"}));
}

TEST_F(ImageIoTest, pngRoundTripGivesBackTheSameBytes) {
  constexpr uint32_t kWidth = 7;
  constexpr uint32_t kHeight = 4;
  std::vector<uint8_t> rgba(kWidth * kHeight * 4);
  for (size_t index = 0; index < rgba.size(); ++index) {
    rgba[index] = static_cast<uint8_t>(index * 37 + 11);  // every byte value pattern, distinct per position
  }
  const std::filesystem::path path = file("image.png");
  writePng(path, kWidth, kHeight, rgba);

  int width = 0;
  int height = 0;
  int channelsInFile = 0;
  uint8_t* decoded = stbi_load(path.c_str(), &width, &height, &channelsInFile, 4);
  ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
  const std::vector<uint8_t> decodedBytes(decoded, decoded + rgba.size());
  stbi_image_free(decoded);
  EXPECT_EQ(width, static_cast<int>(kWidth));
  EXPECT_EQ(height, static_cast<int>(kHeight));
  EXPECT_EQ(channelsInFile, 4);
  EXPECT_EQ(decodedBytes, rgba);
}

TEST_F(ImageIoTest, writingIntoAMissingDirectoryThrowsNamingTheFile) {
  const std::filesystem::path exrPath = file("missing/image.exr");
  expectImageIoErrorNaming(exrPath, [&] { writeExr(exrPath, imageWithHardValues(3)); });
  const std::filesystem::path pngPath = file("missing/image.png");
  const std::vector<uint8_t> rgba(4 * 4 * 4, 128);
  expectImageIoErrorNaming(pngPath, [&] { writePng(pngPath, 4, 4, rgba); });
}

TEST_F(ImageIoTest, readingAMissingFileThrowsNamingTheFile) {
  const std::filesystem::path path = file("absent.exr");
  expectImageIoErrorNaming(path, [&] { readExr(path); });
}

TEST_F(ImageIoTest, readingACorruptFileThrowsNamingTheFile) {
  const std::filesystem::path notExr = file("not_an_image.exr");
  std::ofstream(notExr) << "this is not an OpenEXR file\n";
  expectImageIoErrorNaming(notExr, [&] { readExr(notExr); });

  // A real EXR cut short: the header parses, the pixel data is missing.
  const std::filesystem::path whole = file("whole.exr");
  writeExr(whole, imageWithHardValues(4));
  const std::filesystem::path truncated = file("truncated.exr");
  std::filesystem::copy_file(whole, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(whole) / 2);
  expectImageIoErrorNaming(truncated, [&] { readExr(truncated); });

  const std::filesystem::path empty = file("empty.exr");
  std::ofstream{empty};
  expectImageIoErrorNaming(empty, [&] { readExr(empty); });
}

TEST_F(ImageIoTest, malformedImagesAreRejectedBeforeWriting) {
  FloatImage twoChannels = imageWithHardValues(1);
  twoChannels.channels = 2;
  twoChannels.pixels.resize(size_t{twoChannels.width} * twoChannels.height * 2);
  const std::filesystem::path exrPath = file("two_channels.exr");
  expectImageIoErrorNaming(exrPath, [&] { writeExr(exrPath, twoChannels); });

  FloatImage shortData = imageWithHardValues(3);
  shortData.pixels.pop_back();
  expectImageIoErrorNaming(exrPath, [&] { writeExr(exrPath, shortData); });

  const std::filesystem::path pngPath = file("short.png");
  const std::vector<uint8_t> rgba(4 * 4 * 4 - 1, 0);
  expectImageIoErrorNaming(pngPath, [&] { writePng(pngPath, 4, 4, rgba); });
  EXPECT_FALSE(std::filesystem::exists(exrPath));
  EXPECT_FALSE(std::filesystem::exists(pngPath));
}

}  // namespace
}  // namespace ssvgi::renderer
