#include "image_compare.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <string>

namespace ssvgi::reference {

namespace {

// Rec. 709 / sRGB primaries, the renderer's linear colour space.
constexpr std::array<double, 3> kLuminanceWeights{0.2126, 0.7152, 0.0722};

// Wang et al. 2004: an 11×11 circular-symmetric Gaussian window of σ = 1.5 pixels, K1 = 0.01, K2 = 0.03.
constexpr int kSsimWindowRadius = 5;
constexpr double kSsimWindowSigma = 1.5;
constexpr double kSsimK1 = 0.01;
constexpr double kSsimK2 = 0.03;

// What the error messages call the images: their files at the CLI, their roles in code.
struct ImageNames {
  std::string test;
  std::string reference;
  std::string mask;
};

std::string sizeText(uint32_t width, uint32_t height) { return std::to_string(width) + "x" + std::to_string(height); }

std::string channelsText(uint32_t channels) {
  return std::to_string(channels) + (channels == 1 ? " channel" : " channels");
}

template <typename First, typename Second>
void requireSameSize(const First& first, const std::string& firstName, const Second& second,
                     const std::string& secondName) {
  if (first.width != second.width || first.height != second.height)
    throw ImageCompareError(firstName + " is " + sizeText(first.width, first.height) + " but " + secondName + " is " +
                            sizeText(second.width, second.height) + "; the images must have the same size");
}

void requireDownsampleFits(uint32_t width, uint32_t height, uint32_t k, const std::string& name) {
  if (k == 0 || k > std::min(width, height))
    throw ImageCompareError("cannot downsample " + name + " (" + sizeText(width, height) + ") by " + std::to_string(k) +
                            ": the block size must be 1 to the shorter side");
}

PixelMask maskFromDepth(const FloatImage& depth, const std::string& name) {
  if (depth.channels != 1)
    throw ImageCompareError(
        name + " has " + channelsText(depth.channels) +
        "; a mask is made from a one-channel depth image (view distance, 0 where there is no surface)");
  PixelMask mask{.width = depth.width, .height = depth.height};
  mask.valid.reserve(depth.pixels.size());
  for (float distance : depth.pixels) mask.valid.push_back(distance > 0.0f ? 1 : 0);  // NaN counts as no surface
  return mask;
}

PixelMask allPixelsValid(uint32_t width, uint32_t height) {
  return PixelMask{.width = width, .height = height, .valid = std::vector<uint8_t>(size_t{width} * height, 1)};
}

double luminance(const FloatImage& image, size_t pixel) {
  const float* channels = &image.pixels[pixel * image.channels];
  if (image.channels == 1) return channels[0];
  return kLuminanceWeights[0] * channels[0] + kLuminanceWeights[1] * channels[1] + kLuminanceWeights[2] * channels[2];
}

// The window's weights at offsets −radius..radius; their scale does not matter, every use divides by their sum.
std::array<double, 2 * kSsimWindowRadius + 1> ssimWindowWeights() {
  std::array<double, 2 * kSsimWindowRadius + 1> weights{};
  for (int offset = -kSsimWindowRadius; offset <= kSsimWindowRadius; ++offset)
    weights[size_t(offset + kSsimWindowRadius)] =
        std::exp(-double(offset * offset) / (2.0 * kSsimWindowSigma * kSsimWindowSigma));
  return weights;
}

// Convolves a field with the separable SSIM window, taking what lies outside the image as 0.
std::vector<double> windowSum(const std::vector<double>& field, uint32_t width, uint32_t height) {
  static const auto weights = ssimWindowWeights();
  const auto sumAlong = [&](const std::vector<double>& input, bool horizontal) {
    std::vector<double> output(input.size(), 0.0);
    const int length = int(horizontal ? width : height);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const int centre = int(horizontal ? x : y);
        const int first = std::max(-kSsimWindowRadius, -centre);
        const int last = std::min(kSsimWindowRadius, length - 1 - centre);
        double sum = 0.0;
        for (int offset = first; offset <= last; ++offset) {
          const size_t index =
              horizontal ? size_t{y} * width + size_t(int(x) + offset) : size_t(int(y) + offset) * width + x;
          sum += weights[size_t(offset + kSsimWindowRadius)] * input[index];
        }
        output[size_t{y} * width + x] = sum;
      }
    return output;
  };
  return sumAlong(sumAlong(field, true), false);
}

// Mean SSIM (see ImageComparison::ssim) of two luminance images over the valid pixels, each window weighted by the
// Gaussian times the mask so that invalid pixels (whose values are never read) drop out of every local statistic.
double meanSsim(const std::vector<double>& testLuminance, const std::vector<double>& referenceLuminance,
                const PixelMask& mask, double dynamicRange) {
  const size_t pixelCount = mask.valid.size();
  std::vector<double> weight(pixelCount, 0.0), test(pixelCount, 0.0), reference(pixelCount, 0.0);
  std::vector<double> testSquared(pixelCount, 0.0), referenceSquared(pixelCount, 0.0), product(pixelCount, 0.0);
  for (size_t pixel = 0; pixel < pixelCount; ++pixel) {
    if (!mask.valid[pixel]) continue;
    const double x = testLuminance[pixel], y = referenceLuminance[pixel];
    weight[pixel] = 1.0;
    test[pixel] = x;
    reference[pixel] = y;
    testSquared[pixel] = x * x;
    referenceSquared[pixel] = y * y;
    product[pixel] = x * y;
  }
  const auto sum = [&](const std::vector<double>& field) { return windowSum(field, mask.width, mask.height); };
  const std::vector<double> weightSum = sum(weight), testSum = sum(test), referenceSum = sum(reference);
  const std::vector<double> testSquaredSum = sum(testSquared), referenceSquaredSum = sum(referenceSquared);
  const std::vector<double> productSum = sum(product);

  const double c1 = (kSsimK1 * dynamicRange) * (kSsimK1 * dynamicRange);
  const double c2 = (kSsimK2 * dynamicRange) * (kSsimK2 * dynamicRange);
  double ssimSum = 0.0;
  uint64_t validCount = 0;
  for (size_t pixel = 0; pixel < pixelCount; ++pixel) {
    if (!mask.valid[pixel]) continue;
    const double w = weightSum[pixel];  // > 0: the window's centre is this valid pixel
    const double meanX = testSum[pixel] / w, meanY = referenceSum[pixel] / w;
    const double varianceX = testSquaredSum[pixel] / w - meanX * meanX;
    const double varianceY = referenceSquaredSum[pixel] / w - meanY * meanY;
    const double covariance = productSum[pixel] / w - meanX * meanY;
    ssimSum += ((2.0 * meanX * meanY + c1) * (2.0 * covariance + c2)) /
               ((meanX * meanX + meanY * meanY + c1) * (varianceX + varianceY + c2));
    ++validCount;
  }
  return ssimSum / double(validCount);
}

// (x, y) is a pixel of the downsampled image; the message gives the block's top-left pixel in the named image.
ImageCompareError notFiniteError(const std::string& name, uint32_t x, uint32_t y, uint32_t k) {
  const std::string corner = "(" + std::to_string(x * k) + ", " + std::to_string(y * k) + ")";
  return ImageCompareError(
      name + " has a NaN or infinite value in " +
      (k == 1 ? "the valid pixel at " + corner : "the valid " + sizeText(k, k) + " block at " + corner));
}

ImageComparison compare(const FloatImage& test, const FloatImage& reference, const PixelMask* mask, uint32_t k,
                        const ImageNames& names) {
  requireSameSize(test, names.test, reference, names.reference);
  if (test.channels != reference.channels)
    throw ImageCompareError(names.test + " has " + channelsText(test.channels) + " but " + names.reference + " has " +
                            channelsText(reference.channels) + "; the images must have the same channels");
  if (mask) requireSameSize(*mask, names.mask, reference, names.reference);
  requireDownsampleFits(reference.width, reference.height, k, names.reference);

  const FloatImage testBlocks = boxDownsample(test, k);
  const FloatImage referenceBlocks = boxDownsample(reference, k);
  const PixelMask valid =
      mask ? boxDownsample(*mask, k) : allPixelsValid(referenceBlocks.width, referenceBlocks.height);

  const uint32_t colourChannels = std::min(reference.channels, 3u);
  double absoluteDifferenceSum = 0.0, absoluteReferenceSum = 0.0, squaredDifferenceSum = 0.0;
  double testSum = 0.0, referenceSum = 0.0;
  double referenceLuminanceSum = 0.0;
  std::vector<double> testLuminance(valid.valid.size(), 0.0), referenceLuminance(valid.valid.size(), 0.0);
  ImageComparison comparison{.pixels = valid.valid.size(), .downsample = k};
  for (uint32_t y = 0; y < valid.height; ++y)
    for (uint32_t x = 0; x < valid.width; ++x) {
      if (!valid.isValid(x, y)) continue;
      const size_t pixel = size_t{y} * valid.width + x;
      for (uint32_t channel = 0; channel < colourChannels; ++channel) {
        const double t = testBlocks.pixels[pixel * testBlocks.channels + channel];
        const double r = referenceBlocks.pixels[pixel * referenceBlocks.channels + channel];
        // A NaN or infinity would silently become the whole figure; it is a bug in whichever image holds it.
        if (!std::isfinite(t)) throw notFiniteError(names.test, x, y, k);
        if (!std::isfinite(r)) throw notFiniteError(names.reference, x, y, k);
        absoluteDifferenceSum += std::abs(t - r);
        absoluteReferenceSum += std::abs(r);
        testSum += t;
        referenceSum += r;
        squaredDifferenceSum += (t - r) * (t - r);
      }
      testLuminance[pixel] = luminance(testBlocks, pixel);
      referenceLuminance[pixel] = luminance(referenceBlocks, pixel);
      referenceLuminanceSum += referenceLuminance[pixel];
      ++comparison.validPixels;
    }
  if (comparison.validPixels == 0)
    throw ImageCompareError("nothing to compare: " +
                            (k == 1 ? "no pixel of " + names.mask + " is valid"
                                    : "no " + sizeText(k, k) + " block of " + names.mask + " is wholly valid"));
  const double meanReferenceLuminance = referenceLuminanceSum / double(comparison.validPixels);
  if (!(absoluteReferenceSum > 0.0) || !(meanReferenceLuminance > 0.0))
    throw ImageCompareError(names.reference +
                            " is black over the valid pixels: an error relative to it has no meaning");

  comparison.relativeMeanAbsoluteError = absoluteDifferenceSum / absoluteReferenceSum;
  comparison.meanRatio = referenceSum > 0.0 ? testSum / referenceSum : 0.0;
  comparison.rmse = std::sqrt(squaredDifferenceSum / double(comparison.validPixels * colourChannels));
  comparison.ssim = meanSsim(testLuminance, referenceLuminance, valid, meanReferenceLuminance);
  return comparison;
}

}  // namespace

PixelMask maskFromDepth(const FloatImage& depth) { return maskFromDepth(depth, "the depth image"); }

FloatImage boxDownsample(const FloatImage& image, uint32_t k) {
  assert(image.pixels.size() == size_t{image.width} * image.height * image.channels);
  requireDownsampleFits(image.width, image.height, k, "the image");
  FloatImage blocks{.width = image.width / k, .height = image.height / k, .channels = image.channels};
  blocks.pixels.resize(size_t{blocks.width} * blocks.height * blocks.channels);
  const double blockArea = double(k) * double(k);
  for (uint32_t blockY = 0; blockY < blocks.height; ++blockY)
    for (uint32_t blockX = 0; blockX < blocks.width; ++blockX)
      for (uint32_t channel = 0; channel < image.channels; ++channel) {
        double sum = 0.0;
        for (uint32_t y = blockY * k; y < (blockY + 1) * k; ++y)
          for (uint32_t x = blockX * k; x < (blockX + 1) * k; ++x)
            sum += image.pixels[(size_t{y} * image.width + x) * image.channels + channel];
        blocks.pixels[(size_t{blockY} * blocks.width + blockX) * blocks.channels + channel] = float(sum / blockArea);
      }
  return blocks;
}

PixelMask boxDownsample(const PixelMask& mask, uint32_t k) {
  requireDownsampleFits(mask.width, mask.height, k, "the mask");
  PixelMask blocks{.width = mask.width / k, .height = mask.height / k};
  blocks.valid.resize(size_t{blocks.width} * blocks.height);
  for (uint32_t blockY = 0; blockY < blocks.height; ++blockY)
    for (uint32_t blockX = 0; blockX < blocks.width; ++blockX) {
      bool allValid = true;
      for (uint32_t y = blockY * k; y < (blockY + 1) * k; ++y)
        for (uint32_t x = blockX * k; x < (blockX + 1) * k; ++x) allValid = allValid && mask.isValid(x, y);
      blocks.valid[size_t{blockY} * blocks.width + blockX] = allValid ? 1 : 0;
    }
  return blocks;
}

ImageComparison compareImages(const FloatImage& test, const FloatImage& reference, const PixelMask* mask,
                              uint32_t downsample) {
  return compare(test, reference, mask, downsample, {"the test image", "the reference image", "the mask"});
}

ImageComparison compareExrFiles(const std::filesystem::path& test, const std::filesystem::path& reference,
                                const std::optional<std::filesystem::path>& depthMask, uint32_t downsample) {
  const ImageNames names{test.string(), reference.string(), depthMask ? depthMask->string() : std::string()};
  const FloatImage testImage = renderer::readExr(test);
  const FloatImage referenceImage = renderer::readExr(reference);
  std::optional<PixelMask> mask;
  if (depthMask) mask = maskFromDepth(renderer::readExr(*depthMask), names.mask);
  return compare(testImage, referenceImage, mask ? &*mask : nullptr, downsample, names);
}

}  // namespace ssvgi::reference
