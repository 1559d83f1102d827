#pragma once
// How far an image is from a reference (SPEC §7 "error vs reference"): the figures `ssvgi compare` prints and the
// scenario commands and tests use. CPU only; linear HDR images such as the renderer's irradiance EXRs.
//
// Colour channels are R, G, B (an alpha channel is ignored) or the single channel Y. Every metric is computed over the
// valid pixels only (see PixelMask), after an optional K×K box downsample: GI is low frequency, and averaging blocks
// keeps the path-traced reference's noise out of the figures.
#include "image_io.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ssvgi::reference {

using renderer::FloatImage;

// A comparison that cannot be made: images of different sizes, nothing valid to compare, a black reference, a
// downsampling factor that leaves no pixel. what() is one line naming the images (their files, where known).
class ImageCompareError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Which pixels a comparison counts: those where the renderer drew a surface. Pixels elsewhere may hold anything
// (the sky, zero, NaN) in either image and never reach a metric.
struct PixelMask {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> valid;  // 1 where the pixel counts; row by row from the top, like FloatImage

  bool isValid(uint32_t x, uint32_t y) const { return valid[size_t{y} * width + x] != 0; }
};

// The pixels with a surface, from a one-channel depth image such as the renderer's depth.exr (view distance in
// metres, 0 where there is no surface): valid where the distance is > 0. Throws ImageCompareError for more channels.
PixelMask maskFromDepth(const FloatImage& depth);

// Averages each k×k block into one pixel, every channel alike. The result is ⌊width/k⌋ × ⌊height/k⌋: a partial block
// at the right or bottom edge is dropped rather than averaged over fewer pixels, so that every pixel of the result
// weighs the same. k = 1 returns the image unchanged. Throws ImageCompareError for k = 0 or k larger than a side.
FloatImage boxDownsample(const FloatImage& image, uint32_t k);

// The mask of boxDownsample(image, k): a block is valid only where all of its pixels are. A block that straddles a
// silhouette would otherwise average in pixels that have no surface, whose values mean nothing.
PixelMask boxDownsample(const PixelMask& mask, uint32_t k);

// The metrics, all over the valid pixels of the downsampled images.
struct ImageComparison {
  // Σ|test − reference| / Σ|reference| over the colour channels: 0.1 means the test is off by 10 % of the
  // reference's light on average. This is SPEC §7's "error vs reference".
  double relativeMeanAbsoluteError = 0.0;
  // Σ test / Σ reference over the colour channels: how much of the reference's light the test has in all, whatever
  // its distribution (1.2: 20 % too much; 0 where the reference's sum is not positive). The error above does not
  // say which way it is off.
  double meanRatio = 0.0;
  // sqrt(mean((test − reference)²)) over the colour channels, in the images' own unit (W/m² for irradiance).
  double rmse = 0.0;
  // Mean structural similarity of luminance (Wang, Bovik, Sheikh and Simoncelli 2004, "Image quality assessment: from
  // error visibility to structural similarity"): 1 for identical images, lower as local means, contrast or structure
  // differ. Luminance is Rec. 709's 0.2126 R + 0.7152 G + 0.0722 B. The window is the paper's 11×11 Gaussian with
  // σ = 1.5 pixels, centred on every valid pixel; it is cut at the image border and at invalid pixels and its weights
  // renormalised over what remains (the paper evaluates only windows wholly inside the image, which would leave few
  // pixels of a downsampled image). The constants are the paper's C1 = (0.01 L)² and C2 = (0.03 L)² with the dynamic
  // range L = the reference's mean luminance over the valid pixels: HDR data has no fixed white, and its maximum is
  // set by a few pixels next to a light, which would make the constants swamp the rest of the image. With L the mean,
  // the constants steady only regions darker than a few percent of the average, and the SSIM does not change when
  // both images are scaled alike (light power, units). SSIM is symmetric in the two images for a given L; swapping
  // them changes it only through L, where their mean luminances differ.
  double ssim = 0.0;
  uint64_t validPixels = 0;  // pixels compared, after downsampling
  uint64_t pixels = 0;       // all pixels after downsampling, valid or not
  uint32_t downsample = 1;   // the block size k
};

// Compares `test` with `reference` (same size and channels) over the pixels valid in `mask` (same size; all pixels
// where it is null), after boxDownsample by `downsample` of images and mask. Throws ImageCompareError when the sizes
// or channels differ, no pixel is valid, or the reference is black over the valid pixels (a relative error of
// something against nothing has no meaning).
ImageComparison compareImages(const FloatImage& test, const FloatImage& reference, const PixelMask* mask,
                              uint32_t downsample);

// compareImages on EXR files, the mask from a depth EXR if `depthMask` is given: what `ssvgi compare` runs. A file
// that cannot be read throws renderer::ImageIoError; the errors of compareImages name the files.
ImageComparison compareExrFiles(const std::filesystem::path& test, const std::filesystem::path& reference,
                                const std::optional<std::filesystem::path>& depthMask, uint32_t downsample);

}  // namespace ssvgi::reference
