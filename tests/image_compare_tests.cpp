// Image comparison (reference/image_compare.h): the metrics against values known in closed form, the mask and the
// downsampling rules, and one-line errors naming the images.
#include "image_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>

namespace ssvgi::reference {
namespace {

FloatImage makeImage(uint32_t width, uint32_t height, uint32_t channels,
                     const std::function<float(uint32_t x, uint32_t y, uint32_t channel)>& value) {
  FloatImage image{.width = width, .height = height, .channels = channels};
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (uint32_t channel = 0; channel < channels; ++channel) image.pixels.push_back(value(x, y, channel));
  return image;
}

FloatImage constantImage(uint32_t width, uint32_t height, float value) {
  return makeImage(width, height, 3, [=](uint32_t, uint32_t, uint32_t) { return value; });
}

// Smooth shading with some colour: distinct values everywhere, positive, so every metric is defined.
FloatImage shadedImage(uint32_t width, uint32_t height) {
  return makeImage(width, height, 3, [](uint32_t x, uint32_t y, uint32_t channel) {
    return 1.0f + 0.5f * std::sin(0.7f * float(x)) * std::cos(0.3f * float(y)) + 0.2f * float(channel);
  });
}

float& at(FloatImage& image, uint32_t x, uint32_t y, uint32_t channel) {
  return image.pixels[(size_t{y} * image.width + x) * image.channels + channel];
}

void expectSameFigures(const ImageComparison& actual, const ImageComparison& expected) {
  EXPECT_EQ(actual.relativeMeanAbsoluteError, expected.relativeMeanAbsoluteError);
  EXPECT_EQ(actual.meanRatio, expected.meanRatio);
  EXPECT_EQ(actual.rmse, expected.rmse);
  EXPECT_EQ(actual.ssim, expected.ssim);
  EXPECT_EQ(actual.validPixels, expected.validPixels);
  EXPECT_EQ(actual.pixels, expected.pixels);
  EXPECT_EQ(actual.downsample, expected.downsample);
}

// Runs `action`, which must throw `Error` with a one-line message containing every one of `parts`.
template <typename Error = ImageCompareError, typename Action>
void expectErrorMentioning(Action action, std::initializer_list<std::string> parts) {
  try {
    action();
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    const std::string message = error.what();
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(ImageCompare, anImageAgainstItselfHasNoErrorAndAnSsimOfOne) {
  const FloatImage image = shadedImage(16, 12);
  for (uint32_t downsample : {1u, 2u, 3u}) {
    SCOPED_TRACE("downsample " + std::to_string(downsample));
    const ImageComparison comparison = compareImages(image, image, nullptr, downsample);
    EXPECT_EQ(comparison.relativeMeanAbsoluteError, 0.0);
    EXPECT_EQ(comparison.rmse, 0.0);
    EXPECT_EQ(comparison.ssim, 1.0);
    EXPECT_EQ(comparison.validPixels, (16 / downsample) * (12 / downsample));
    EXPECT_EQ(comparison.downsample, downsample);
  }
}

TEST(ImageCompare, scalingByOnePointOneGivesARelativeErrorOfExactlyATenth) {
  // Multiples of 10 times 1.1 are exact in float, so the only rounding left is the final division.
  const FloatImage reference = makeImage(
      6, 4, 3, [](uint32_t x, uint32_t y, uint32_t channel) { return 10.0f * float(1 + x + 3 * y + channel); });
  FloatImage test = reference;
  for (float& value : test.pixels) value = value / 10.0f * 11.0f;
  EXPECT_DOUBLE_EQ(compareImages(test, reference, nullptr, 1).relativeMeanAbsoluteError, 0.1);
}

// The mean ratio says which way an image is off, which the relative error does not: 20 % too much on one half and
// 20 % too little on the other is a relative error of 0.2 and a mean ratio of 1; 20 % too little everywhere, 0.2 and 0.8.
TEST(ImageCompare, theMeanRatioSaysWhetherTheTestHasMoreOrLessLightInAll) {
  const FloatImage reference = constantImage(8, 8, 5.0f);
  FloatImage split = reference;
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x)
      for (uint32_t channel = 0; channel < reference.channels; ++channel) at(split, x, y, channel) = x < 4 ? 6.0f : 4.0f;
  const ImageComparison balanced = compareImages(split, reference, nullptr, 1);
  EXPECT_DOUBLE_EQ(balanced.relativeMeanAbsoluteError, 0.2);
  EXPECT_DOUBLE_EQ(balanced.meanRatio, 1.0);
  const ImageComparison darker = compareImages(constantImage(8, 8, 4.0f), reference, nullptr, 1);
  EXPECT_DOUBLE_EQ(darker.relativeMeanAbsoluteError, 0.2);
  EXPECT_DOUBLE_EQ(darker.meanRatio, 0.8);
}

TEST(ImageCompare, aConstantOffsetOnAConstantImageGivesThatOffsetAsRmse) {
  const ImageComparison comparison = compareImages(constantImage(8, 8, 2.5f), constantImage(8, 8, 2.0f), nullptr, 1);
  EXPECT_EQ(comparison.rmse, 0.5);
  EXPECT_EQ(comparison.relativeMeanAbsoluteError, 0.25);
}

TEST(ImageCompare, ssimOfConstantImagesIsThePapersLuminanceTermWithTheReferenceMeanAsDynamicRange) {
  // No contrast, so SSIM is (2 μx μy + C1) / (μx² + μy² + C1) with C1 = (0.01 L)², L = μy (Rec. 709 weights sum to 1).
  const double testLuminance = 2.5, referenceLuminance = 2.0;
  const double c1 = (0.01 * referenceLuminance) * (0.01 * referenceLuminance);
  const double expected = (2.0 * testLuminance * referenceLuminance + c1) /
                          (testLuminance * testLuminance + referenceLuminance * referenceLuminance + c1);
  const FloatImage test = constantImage(8, 8, 2.5f), reference = constantImage(8, 8, 2.0f);
  EXPECT_NEAR(compareImages(test, reference, nullptr, 1).ssim, expected, 1e-12);

  // Masked-out pixels inside the windows must not bring in contrast of their own.
  PixelMask mask{.width = 8, .height = 8, .valid = std::vector<uint8_t>(64, 1)};
  for (size_t pixel = 0; pixel < mask.valid.size(); pixel += 5) mask.valid[pixel] = 0;
  EXPECT_NEAR(compareImages(test, reference, &mask, 1).ssim, expected, 1e-12);
}

TEST(ImageCompare, aCheckerboardOfPlusMinusDVanishesWhenDownsampledByTwo) {
  const FloatImage reference = constantImage(8, 6, 1.0f);
  const FloatImage test =
      makeImage(8, 6, 3, [](uint32_t x, uint32_t y, uint32_t) { return (x + y) % 2 == 0 ? 1.25f : 0.75f; });

  const ImageComparison fullResolution = compareImages(test, reference, nullptr, 1);
  EXPECT_EQ(fullResolution.relativeMeanAbsoluteError, 0.25);
  EXPECT_EQ(fullResolution.rmse, 0.25);
  EXPECT_LT(fullResolution.ssim, 1.0);

  const ImageComparison downsampled = compareImages(test, reference, nullptr, 2);
  EXPECT_EQ(downsampled.relativeMeanAbsoluteError, 0.0);
  EXPECT_EQ(downsampled.rmse, 0.0);
  EXPECT_EQ(downsampled.ssim, 1.0);
  EXPECT_EQ(downsampled.validPixels, 12u);
}

TEST(ImageCompare, maskFromDepthIsValidWhereTheViewDistanceIsPositive) {
  const float distances[] = {0.0f, 2.5f, -1.0f, std::numeric_limits<float>::quiet_NaN(), 1e-6f, 0.0f};
  const FloatImage depth = makeImage(3, 2, 1, [&](uint32_t x, uint32_t y, uint32_t) { return distances[y * 3 + x]; });
  const PixelMask mask = maskFromDepth(depth);
  EXPECT_EQ(mask.width, 3u);
  EXPECT_EQ(mask.height, 2u);
  EXPECT_EQ(mask.valid, (std::vector<uint8_t>{0, 1, 0, 0, 1, 0}));

  expectErrorMentioning([] { maskFromDepth(constantImage(3, 2, 1.0f)); }, {"depth image", "3 channels"});
}

TEST(ImageCompare, pixelsOutsideTheMaskChangeNothingEvenWhenHugeOrNaN) {
  const FloatImage reference = shadedImage(12, 8);
  FloatImage test = reference;
  for (float& value : test.pixels) value *= 1.05f;
  FloatImage depth = makeImage(12, 8, 1, [](uint32_t, uint32_t, uint32_t) { return 3.0f; });
  at(depth, 5, 3, 0) = 0.0f;  // no surface at (5, 3)
  const PixelMask mask = maskFromDepth(depth);

  for (uint32_t downsample : {1u, 2u}) {
    SCOPED_TRACE("downsample " + std::to_string(downsample));
    const ImageComparison clean = compareImages(test, reference, &mask, downsample);
    EXPECT_EQ(clean.validPixels, 12 * 8 / (downsample * downsample) - 1);

    FloatImage hugeTest = test;
    at(hugeTest, 5, 3, 1) = 1e30f;
    expectSameFigures(compareImages(hugeTest, reference, &mask, downsample), clean);
    EXPECT_GT(compareImages(hugeTest, reference, nullptr, downsample).rmse, 1e20);  // without the mask it counts

    FloatImage nanTest = test, nanReference = reference;
    at(nanTest, 5, 3, 0) = std::numeric_limits<float>::quiet_NaN();
    at(nanReference, 5, 3, 2) = std::numeric_limits<float>::infinity();
    expectSameFigures(compareImages(nanTest, nanReference, &mask, downsample), clean);
  }
}

TEST(ImageCompare, boxDownsampleAveragesEachBlockExactlyAndDropsPartialEdgeBlocks) {
  // 5×3 by 2: the fifth column and third row do not fill a block.
  const FloatImage image = makeImage(5, 3, 3, [](uint32_t x, uint32_t y, uint32_t channel) {
    return float(x) + 10.0f * float(y) + 100.0f * float(channel);
  });
  const FloatImage blocks = boxDownsample(image, 2);
  EXPECT_EQ(blocks.width, 2u);
  EXPECT_EQ(blocks.height, 1u);
  EXPECT_EQ(blocks.channels, 3u);
  // (0 + 1 + 10 + 11) / 4 and (2 + 3 + 12 + 13) / 4, plus 100 per channel.
  EXPECT_EQ(blocks.pixels, (std::vector<float>{5.5f, 105.5f, 205.5f, 7.5f, 107.5f, 207.5f}));

  EXPECT_EQ(boxDownsample(image, 1).pixels, image.pixels);
  const FloatImage whole = boxDownsample(image, 3);
  ASSERT_EQ(whole.pixels.size(), 3u);
  EXPECT_FLOAT_EQ(whole.pixels[0], 11.0f);  // mean of x 0..2 (1) plus mean of 10 y over y 0..2 (10)
}

TEST(ImageCompare, aDownsampledMaskBlockIsValidOnlyWhereAllItsPixelsAre) {
  PixelMask mask{.width = 5, .height = 4, .valid = std::vector<uint8_t>(20, 1)};
  mask.valid[0 * 5 + 3] = 0;  // spoils block (1, 0)
  mask.valid[3 * 5 + 4] = 0;  // in the dropped fifth column: spoils nothing
  const PixelMask blocks = boxDownsample(mask, 2);
  EXPECT_EQ(blocks.width, 2u);
  EXPECT_EQ(blocks.height, 2u);
  EXPECT_EQ(blocks.valid, (std::vector<uint8_t>{1, 0, 1, 1}));
}

TEST(ImageCompare, ssimDropsBelowOneForAStructuralChangeAndIsSymmetric) {
  // Stripes two pixels wide, and the same stripes moved by two pixels: the same mean, opposite structure.
  const auto stripes = [](uint32_t phase) {
    return makeImage(16, 16, 3, [=](uint32_t x, uint32_t, uint32_t) { return ((x + phase) / 2) % 2 ? 1.5f : 0.5f; });
  };
  const FloatImage reference = stripes(0), test = stripes(2);
  const double forward = compareImages(test, reference, nullptr, 1).ssim;
  const double backward = compareImages(reference, test, nullptr, 1).ssim;
  EXPECT_LT(forward, 0.5);
  EXPECT_DOUBLE_EQ(forward, backward);

  // A milder change, a brighter square, still shows.
  FloatImage square = reference;
  for (uint32_t y = 4; y < 8; ++y)
    for (uint32_t x = 4; x < 8; ++x)
      for (uint32_t channel = 0; channel < 3; ++channel) at(square, x, y, channel) += 0.5f;
  const double squareSsim = compareImages(square, reference, nullptr, 1).ssim;
  EXPECT_LT(squareSsim, 0.99);
  EXPECT_GT(squareSsim, forward);
}

TEST(ImageCompare, ssimIsUnchangedWhenBothImagesAreScaledAlike) {
  // HDR images have no fixed white: changing the light's power or the unit must not change the structural figure.
  const FloatImage reference = shadedImage(16, 12);
  FloatImage test = reference;
  for (uint32_t x = 3; x < 9; ++x) at(test, x, 5, 1) *= 1.5f;
  const double ssim = compareImages(test, reference, nullptr, 1).ssim;
  ASSERT_LT(ssim, 0.999);

  FloatImage brighterTest = test, brighterReference = reference;
  for (float& value : brighterTest.pixels) value *= 64.0f;  // a power of two: the scaled images are exact
  for (float& value : brighterReference.pixels) value *= 64.0f;
  EXPECT_DOUBLE_EQ(compareImages(brighterTest, brighterReference, nullptr, 1).ssim, ssim);
}

TEST(ImageCompare, aFewBrightPixelsDoNotMakeSsimBlindToTheRest) {
  // A 25 % error everywhere but one pixel next to a light. Taking the dynamic range from the maximum (1000) would
  // make C1 and C2 dwarf the rest of the image and give an SSIM of 0.999; the mean keeps the error visible.
  FloatImage reference = constantImage(32, 32, 1.0f);
  for (uint32_t channel = 0; channel < 3; ++channel) at(reference, 0, 0, channel) = 1000.0f;
  FloatImage test = reference;
  for (float& value : test.pixels) value *= 1.25f;
  EXPECT_LT(compareImages(test, reference, nullptr, 1).ssim, 0.99);
}

TEST(ImageCompare, ssimWeighsRec709LuminanceSoAChangeOfHueAloneKeepsItAtOne) {
  // Moving 0.7152 d into red and 0.2126 d out of green leaves 0.2126 R + 0.7152 G unchanged.
  const FloatImage reference = shadedImage(16, 12);
  FloatImage test = reference;
  constexpr float kShift = 0.5f;
  for (uint32_t y = 0; y < 12; ++y)
    for (uint32_t x = 0; x < 16; ++x) {
      at(test, x, y, 0) += 0.7152f * kShift;
      at(test, x, y, 1) -= 0.2126f * kShift;
    }
  const ImageComparison comparison = compareImages(test, reference, nullptr, 1);
  EXPECT_GT(comparison.relativeMeanAbsoluteError, 0.05);
  EXPECT_NEAR(comparison.ssim, 1.0, 1e-6);
}

TEST(ImageCompare, anAlphaChannelIsIgnored) {
  const auto rgba = [](float alpha) {
    return makeImage(8, 8, 4,
                     [=](uint32_t x, uint32_t, uint32_t channel) { return channel == 3 ? alpha : float(1 + x); });
  };
  const ImageComparison comparison = compareImages(rgba(0.0f), rgba(1.0f), nullptr, 1);
  EXPECT_EQ(comparison.relativeMeanAbsoluteError, 0.0);
  EXPECT_EQ(comparison.rmse, 0.0);
}

TEST(ImageCompare, comparisonsThatMeanNothingAreRefusedWithOneLine) {
  const FloatImage image = shadedImage(8, 6);
  expectErrorMentioning([&] { compareImages(image, constantImage(8, 6, 0.0f), nullptr, 1); },
                        {"the reference image is black"});
  const FloatImage grey = makeImage(8, 6, 1, [](uint32_t, uint32_t, uint32_t) { return 1.0f; });
  expectErrorMentioning([&] { compareImages(image, grey, nullptr, 1); },
                        {"the test image has 3 channels", "the reference image has 1 channel"});
  expectErrorMentioning([&] { compareImages(image, shadedImage(6, 8), nullptr, 1); },
                        {"the test image is 8x6", "the reference image is 6x8"});

  PixelMask nothingValid{.width = 8, .height = 6, .valid = std::vector<uint8_t>(48, 0)};
  expectErrorMentioning([&] { compareImages(image, image, &nothingValid, 1); }, {"no pixel of the mask is valid"});
  PixelMask checkered = nothingValid;
  for (size_t pixel = 0; pixel < checkered.valid.size(); pixel += 2) checkered.valid[pixel] = 1;
  expectErrorMentioning([&] { compareImages(image, image, &checkered, 2); }, {"no 2x2 block of the mask"});

  expectErrorMentioning([&] { compareImages(image, image, nullptr, 0); }, {"by 0"});
  expectErrorMentioning([&] { compareImages(image, image, nullptr, 7); }, {"8x6", "by 7"});

  FloatImage broken = image;
  at(broken, 5, 3, 1) = std::numeric_limits<float>::quiet_NaN();
  expectErrorMentioning([&] { compareImages(broken, image, nullptr, 1); }, {"the test image", "pixel at (5, 3)"});
  expectErrorMentioning([&] { compareImages(image, broken, nullptr, 2); },
                        {"the reference image", "2x2 block at (4, 2)"});
}

// Each test gets its own fresh directory for its EXR files.
class ImageCompareFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (std::filesystem::temp_directory_path() / "ssvgi_image_compare_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    directory_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::filesystem::path write(const std::string& name, const FloatImage& image) const {
    const std::filesystem::path path = directory_ / name;
    renderer::writeExr(path, image);
    return path;
  }

 private:
  std::filesystem::path directory_;
};

TEST_F(ImageCompareFiles, imagesOfDifferentSizesAreRefusedNamingBothFilesAndSizes) {
  const auto test = write("test.exr", shadedImage(8, 8));
  const auto reference = write("reference.exr", shadedImage(4, 6));
  expectErrorMentioning([&] { compareExrFiles(test, reference, std::nullopt, 1); },
                        {test.string() + " is 8x8", reference.string() + " is 4x6"});
}

TEST_F(ImageCompareFiles, aMaskOfAnotherSizeOrWithColourIsRefusedNamingItsFile) {
  const auto test = write("test.exr", shadedImage(8, 8));
  const auto reference = write("reference.exr", shadedImage(8, 8));
  const auto smallDepth =
      write("small_depth.exr", makeImage(4, 4, 1, [](uint32_t, uint32_t, uint32_t) { return 1.0f; }));
  expectErrorMentioning([&] { compareExrFiles(test, reference, smallDepth, 1); },
                        {smallDepth.string() + " is 4x4", reference.string() + " is 8x8"});
  const auto colourDepth = write("colour_depth.exr", shadedImage(8, 8));
  expectErrorMentioning([&] { compareExrFiles(test, reference, colourDepth, 1); },
                        {colourDepth.string() + " has 3 channels"});
}

TEST_F(ImageCompareFiles, anUnreadableFileGivesTheImageIoErrorNamingIt) {
  const auto image = write("image.exr", shadedImage(8, 8));
  const auto missing = image.parent_path() / "missing.exr";
  expectErrorMentioning<renderer::ImageIoError>([&] { compareExrFiles(missing, image, std::nullopt, 1); },
                                                {missing.string()});
  expectErrorMentioning<renderer::ImageIoError>([&] { compareExrFiles(image, image, missing, 1); }, {missing.string()});
  const auto corrupt = image.parent_path() / "corrupt.exr";
  std::ofstream(corrupt) << "not an EXR\n";
  expectErrorMentioning<renderer::ImageIoError>([&] { compareExrFiles(image, corrupt, std::nullopt, 1); },
                                                {corrupt.string()});
}

TEST_F(ImageCompareFiles, comparingFilesGivesTheFiguresOfComparingTheImages) {
  const FloatImage reference = shadedImage(12, 8);
  FloatImage test = reference;
  for (uint32_t x = 2; x < 7; ++x) at(test, x, 4, 0) += 0.3f;
  const FloatImage depth =
      makeImage(12, 8, 1, [](uint32_t x, uint32_t y, uint32_t) { return x + y < 4 ? 0.0f : float(x + y); });
  const PixelMask mask = maskFromDepth(depth);
  expectSameFigures(
      compareExrFiles(write("test.exr", test), write("reference.exr", reference), write("depth.exr", depth), 2),
      compareImages(test, reference, &mask, 2));
}

}  // namespace
}  // namespace ssvgi::reference
