#include "commands.h"

#include "image_compare.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>

namespace ssvgi::cli {

namespace {

struct CompareOptions {
  std::string test;
  std::string reference;
  std::optional<std::string> maskFrom;
  uint32_t downsample = 1;
  bool json = false;
};

int runCompare(const CompareOptions& options) {
  const std::optional<std::filesystem::path> depthMask =
      options.maskFrom ? std::optional<std::filesystem::path>(*options.maskFrom) : std::nullopt;
  const reference::ImageComparison comparison =
      reference::compareExrFiles(options.test, options.reference, depthMask, options.downsample);

  if (options.json) {
    const nlohmann::json result = {{"relativeMeanAbsoluteError", comparison.relativeMeanAbsoluteError},
                                   {"meanRatio", comparison.meanRatio},
                                   {"rmse", comparison.rmse},
                                   {"ssim", comparison.ssim},
                                   {"validPixels", comparison.validPixels},
                                   {"downsample", comparison.downsample}};
    std::printf("%s\n", result.dump(2).c_str());
    return 0;
  }
  const std::string k = std::to_string(comparison.downsample);
  const std::string blocks = comparison.downsample == 1 ? "full resolution" : k + "x" + k + " blocks";
  const std::string mask = options.maskFrom ? "mask: depth > 0 in " + *options.maskFrom : "no mask";
  std::printf("test       %s\nreference  %s\n", options.test.c_str(), options.reference.c_str());
  std::printf("pixels     %llu of %llu compared (%s; %s)\n\n", static_cast<unsigned long long>(comparison.validPixels),
              static_cast<unsigned long long>(comparison.pixels), blocks.c_str(), mask.c_str());
  std::printf("relative mean absolute error  %.4g\n", comparison.relativeMeanAbsoluteError);
  std::printf("mean ratio (test/reference)   %.4g\n", comparison.meanRatio);
  std::printf("RMSE                          %.4g\n", comparison.rmse);
  std::printf("SSIM (luminance)              %.4f\n", comparison.ssim);
  return 0;
}

}  // namespace

CommandRunner addCompareCommand(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command =
      app.add_subcommand("compare", "Compare a linear EXR with a reference: relative mean absolute error, RMSE, SSIM");
  command->footer(
      "Relative mean absolute error: sum |test - reference| / sum |reference| over the valid pixels and colour "
      "channels (R, G, B or Y). RMSE: in the images' unit. SSIM: Wang et al. 2004 on Rec. 709 luminance, 11x11 "
      "Gaussian window (sigma 1.5), dynamic range L = the reference's mean luminance. The exit code is 0 whatever the "
      "figures: a comparison is not a pass or a fail.");
  command->add_option("test", options->test, "The image to judge (EXR: Y, RGB or RGBA)")->required();
  command->add_option("reference", options->reference, "The reference image, same size and channels")->required();
  command->add_option("--mask-from", options->maskFrom,
                      "Compare only where this depth EXR (as written by render: view distance, 0 where there is no "
                      "surface) is > 0");
  command
      ->add_option("--downsample", options->downsample,
                   "Average KxK blocks (K from 1, none, to the shorter side) before comparing, keeping the "
                   "reference's noise out of the figures; with a mask, a block counts only where all its pixels "
                   "are valid; partial blocks at the edges are dropped")
      ->capture_default_str();
  command->add_flag("--json", options->json,
                    "Print one JSON object: relativeMeanAbsoluteError, meanRatio, rmse, ssim, validPixels, downsample");
  return [options] { return runCompare(*options); };
}

}  // namespace ssvgi::cli
