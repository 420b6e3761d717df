// The numerical-stability suite (tools/stability/) with its thresholds: no non-finite sample anywhere, no
// ray through a closed mesh or solid, no acne on a grazing plane, exact long accumulations, images that do
// not change with scale or distance from the origin, and GPU agreeing with the double-precision reference.
// The analytic shapes' cases (grazing rays, edges, coincident CSG operands, scales 1e-4 and 1e4) run as a
// test of their own.
#include <gtest/gtest.h>

#include "gpu/vulkan_context.h"
#include "stability/stability_suite.h"
#include "support/reference_comparison.h"
#include "support/temporary_folder.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

std::vector<StabilityResult> runCases(StabilityCases cases, uint32_t& validationMessages) {
    ContextOptions contextOptions;
    contextOptions.validation = true;
    const VulkanContext context(contextOptions);
    StabilityOptions options;
    options.sourceDir = test::sourceDir();
    options.workDir = test::temporaryFolder();
    options.shaderCacheDir = test::shaderCacheDir();
    options.dumpDir = options.workDir / "images";
    options.cases = cases;
    std::vector<StabilityResult> results = runStabilitySuite(context, options);
    validationMessages = context.validationMessages();
    return results;
}

void expectThresholds(const std::vector<StabilityResult>& results) {
    for (const StabilityResult& r : results) {
        SCOPED_TRACE(r.group + ": " + r.name);
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        if (r.leaks) {
            EXPECT_EQ(*r.leaks, 0u) << r.note;
        }
        if (r.wrongHits) {
            EXPECT_EQ(*r.wrongHits, 0u) << r.note;
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
    std::printf("%s", stabilityTable(results).c_str());
}

TEST(Stability, EveryCaseHoldsItsThresholds) {
    uint32_t validationMessages = 0;
    const std::vector<StabilityResult> results = runCases(StabilityCases::WithoutShapes, validationMessages);
    ASSERT_GE(results.size(), 25u);
    expectThresholds(results);
    EXPECT_EQ(validationMessages, 0u);
}

TEST(Stability, EveryShapeCaseHoldsItsThresholds) {
    uint32_t validationMessages = 0;
    const std::vector<StabilityResult> results = runCases(StabilityCases::ShapesOnly, validationMessages);
    ASSERT_GE(results.size(), 11u);
    expectThresholds(results);
    for (const StabilityResult& r : results) {
        if (!r.note.empty()) std::printf("%s: %s: %s\n", r.group.c_str(), r.name.c_str(), r.note.c_str());
    }
    EXPECT_EQ(validationMessages, 0u);
}

}  // namespace
}  // namespace vkrt
