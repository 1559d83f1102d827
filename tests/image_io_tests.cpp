// EXR and PNG files (renderer/image_io.h): exact round trips, channel naming, one-line errors naming the file for
// corrupt, cut or absurd files and for what is no file at all, and files replaced together or not at all.
#include "image_io.h"

#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <tinyexr.h>

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
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

std::vector<uint8_t> fileBytes(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

std::string fileText(const std::filesystem::path& path) {
  std::ifstream stream(path);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

std::set<std::string> filesIn(const std::filesystem::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

// An EXR of `image` with another compression than writeExr's ZIP, written by tinyexr itself.
std::vector<uint8_t> exrWithCompression(const FloatImage& image, int compression) {
  std::vector<std::vector<float>> planes(image.channels, std::vector<float>(size_t{image.width} * image.height));
  std::vector<uint8_t*> planePointers;
  for (uint32_t channel = 0; channel < image.channels; ++channel) {
    for (size_t pixel = 0; pixel < planes[channel].size(); ++pixel) {
      planes[channel][pixel] = image.pixels[pixel * image.channels + channel];
    }
    planePointers.push_back(reinterpret_cast<uint8_t*>(planes[channel].data()));
  }
  std::vector<EXRChannelInfo> channels(image.channels);
  const char* names[] = {"R", "G", "B"};  // tinyexr needs no particular order to read its own file back
  for (uint32_t channel = 0; channel < image.channels; ++channel) std::strcpy(channels[channel].name, names[channel]);
  std::vector<int> pixelTypes(image.channels, TINYEXR_PIXELTYPE_FLOAT);
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(image.channels);
  header.channels = channels.data();
  header.pixel_types = pixelTypes.data();
  header.requested_pixel_types = pixelTypes.data();
  header.compression_type = compression;
  EXRImage exrImage;
  InitEXRImage(&exrImage);
  exrImage.num_channels = static_cast<int>(image.channels);
  exrImage.width = static_cast<int>(image.width);
  exrImage.height = static_cast<int>(image.height);
  exrImage.images = planePointers.data();
  unsigned char* encoded = nullptr;
  const char* message = nullptr;
  const size_t size = SaveEXRImageToMemory(&exrImage, &header, &encoded, &message);
  EXPECT_GT(size, 0u) << (message != nullptr ? message : "");
  std::vector<uint8_t> bytes(encoded, encoded + size);
  std::free(encoded);
  return bytes;
}

// Where the value of the header attribute `name` of type `type` starts in an EXR file's bytes (after its size).
size_t exrAttributeValue(const std::vector<uint8_t>& bytes, const std::string& name, const std::string& type) {
  const std::string key = name + '\0' + type + '\0';
  const auto found = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
  EXPECT_NE(found, bytes.end()) << name;
  return static_cast<size_t>(found - bytes.begin()) + key.size() + sizeof(int32_t);
}

TEST_F(ImageIoTest, anExrCutShortAnywhereIsRefusedWithOneLine) {
  // ssvgi's own final.exr cut by one byte once made tinyexr free the image and readExr free it again.
  const std::filesystem::path whole = file("whole.exr");
  writeExr(whole, imageWithHardValues(3));
  const std::vector<uint8_t> bytes = fileBytes(whole);
  const std::filesystem::path cut = file("cut.exr");
  // Every length over the pixel data at the end, where decoding fails after the image is allocated; a sample before.
  for (size_t length = 0; length < bytes.size(); length += bytes.size() - length > 128 ? 13 : 1) {
    SCOPED_TRACE("cut to " + std::to_string(length) + " of " + std::to_string(bytes.size()) + " bytes");
    writeBytes(cut, {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length)});
    expectImageIoErrorNaming(cut, [&] { readExr(cut); });
  }
}

TEST_F(ImageIoTest, anExrWhoseHeaderSaysPizButWhoseDataIsRawIsRefused) {
  const FloatImage image = imageWithHardValues(3);
  std::vector<uint8_t> bytes = exrWithCompression(image, TINYEXR_COMPRESSIONTYPE_NONE);
  const std::filesystem::path raw = file("raw.exr");
  writeBytes(raw, bytes);
  EXPECT_EQ(readExr(raw).pixels.size(), image.pixels.size());  // the file is good until its header lies

  bytes[exrAttributeValue(bytes, "compression", "compression")] = TINYEXR_COMPRESSIONTYPE_PIZ;
  const std::filesystem::path piz = file("piz.exr");
  writeBytes(piz, bytes);
  expectImageIoErrorNaming(piz, [&] { readExr(piz); });
}

TEST_F(ImageIoTest, aHeaderClaimingMorePixelsThanReadIsRefusedBeforeDecoding) {
  // 8,000,000 × 16 pixels fit one ZIP block, so tinyexr would allocate 1.5 GB before finding the data missing.
  std::vector<uint8_t> bytes = fileBytes([&] {
    writeExr(file("small.exr"), imageWithHardValues(3));
    return file("small.exr");
  }());
  const size_t window = exrAttributeValue(bytes, "dataWindow", "box2i");
  const int32_t box[4] = {0, 0, 7'999'999, 15};  // min x, min y, max x, max y
  std::memcpy(&bytes[window], box, sizeof(box));
  const std::filesystem::path huge = file("huge.exr");
  writeBytes(huge, bytes);
  try {
    readExr(huge);
    ADD_FAILURE() << "read";
  } catch (const ImageIoError& error) {
    EXPECT_NE(std::string(error.what()).find("8000000x16"), std::string::npos) << error.what();
  }
}

TEST_F(ImageIoTest, devicesFoldersAndPipesAreRefusedWithoutReadingThem) {
  // Reading /dev/zero never ends; opening a pipe waits for a writer.
  const std::filesystem::path pipe = file("pipe.exr");
  ASSERT_EQ(mkfifo(pipe.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  for (const std::filesystem::path& path : {std::filesystem::path("/dev/zero"), pipe, file("")}) {
    SCOPED_TRACE(path.string());
    expectImageIoErrorNaming(path, [&] { readExr(path); });
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST_F(ImageIoTest, aFileLargerThanTheBoundIsRefusedBeforeReading) {
  const std::filesystem::path large = file("large.exr");
  std::ofstream{large};
  std::filesystem::resize_file(large, kMaxExrFileBytes + 1);  // sparse: takes no disk space
  try {
    readExr(large);
    ADD_FAILURE() << "read";
  } catch (const ImageIoError& error) {
    EXPECT_NE(std::string(error.what()).find(std::to_string(kMaxExrFileBytes + 1) + " bytes"), std::string::npos)
        << error.what();
  }
}

TEST_F(ImageIoTest, stagedFilesReplaceTheirDestinationsOnlyOnCommit) {
  const std::filesystem::path text = file("stats.json");
  const std::filesystem::path image = file("final.exr");
  std::ofstream(text) << "old";
  {
    StagedFiles files;
    files.writeText(text, "new");
    files.writeExr(image, imageWithHardValues(3));
    EXPECT_EQ(fileText(text), "old");
    EXPECT_FALSE(std::filesystem::exists(image));
    files.commit();
  }
  EXPECT_EQ(fileText(text), "new");
  expectBitIdentical(readExr(image), imageWithHardValues(3));
  EXPECT_EQ(filesIn(file("")), (std::set<std::string>{"stats.json", "final.exr"}));
}

TEST_F(ImageIoTest, anErrorHalfWayLeavesEveryDestinationAsItWasAndNoTemporaryFile) {
  const std::filesystem::path text = file("stats.json");
  const std::filesystem::path image = file("final.exr");
  std::ofstream(text) << "old";
  std::ofstream(image) << "old image";
  FloatImage malformed = imageWithHardValues(3);
  malformed.pixels.pop_back();
  {
    StagedFiles files;
    files.writeText(text, "new");
    expectImageIoErrorNaming(image, [&] { files.writeExr(image, malformed); });
  }
  EXPECT_EQ(fileText(text), "old");
  EXPECT_EQ(fileText(image), "old image");
  EXPECT_EQ(filesIn(file("")), (std::set<std::string>{"stats.json", "final.exr"}));
}

TEST_F(ImageIoTest, commitRenamesNothingWhenADestinationIsAFolder) {
  const std::filesystem::path text = file("stats.json");
  const std::filesystem::path folder = file("final.png");
  std::ofstream(text) << "old";
  std::filesystem::create_directory(folder);
  {
    StagedFiles files;
    files.writeText(text, "new");
    files.writeText(folder, "not an image");
    expectImageIoErrorNaming(folder, [&] { files.commit(); });
  }
  EXPECT_EQ(fileText(text), "old");
  EXPECT_TRUE(std::filesystem::is_directory(folder));
  EXPECT_EQ(filesIn(file("")), (std::set<std::string>{"stats.json", "final.png"}));
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
