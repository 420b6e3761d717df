// The numerical-stability suite (tools/stability/) with its thresholds: no non-finite sample anywhere, no
// ray through a closed mesh, no acne on a grazing plane, exact long accumulations, images that do not
// change with scale or distance from the origin, and GPU agreeing with the double-precision reference.
#include <gtest/gtest.h>

#include "gpu/vulkan_context.h"
#include "stability/stability_suite.h"
#include "support/reference_comparison.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

TEST(Stability, EveryCaseHoldsItsThresholds) {
    ContextOptions contextOptions;
    contextOptions.validation = true;
    const VulkanContext context(contextOptions);
    StabilityOptions options;
    options.sourceDir = test::sourceDir();
    options.workDir = test::temporaryFolder();
    options.shaderCacheDir = test::shaderCacheDir();
    options.dumpDir = options.workDir / "images";
    const std::vector<StabilityResult> results = runStabilitySuite(context, options);
    ASSERT_GE(results.size(), 25u);
    for (const StabilityResult& r : results) {
        SCOPED_TRACE(r.group + ": " + r.name);
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        if (r.leaks) {
            EXPECT_EQ(*r.leaks, 0u);
        }
        if (r.acne) {
            EXPECT_EQ(*r.acne, 0.0);
        }
        if (r.accumulationError) {
            EXPECT_LE(*r.accumulationError, 1e-6);
        }
        if (r.invarianceOff) {
            EXPECT_LE(*r.invarianceOff, 0.001);
            EXPECT_LE(*r.invarianceMeanRelative, 1e-4);
        }
        // Every rendered case agrees with the double-precision reference, coplanar faces included (ties
        // between them go to the smaller triangle index on both sides).
        if (!r.leaks && !r.accumulationError) {
            EXPECT_LE(r.gpuVsCpuOff, test::kMaxFractionOff);
            EXPECT_LE(r.gpuVsCpuMeanRelative, test::kMaxMeanRelativeError);
        }
    }
    EXPECT_EQ(context.validationMessages(), 0u);
    std::printf("%s", stabilityTable(results).c_str());
}

}  // namespace
}  // namespace vkrt
