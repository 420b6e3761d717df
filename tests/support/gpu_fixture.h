// The fixture of every test on the Vulkan device: one validated VulkanContext per test program, and every
// test must leave it without validation messages. With the helpers those tests share.
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "bvh/flat_bvh.h"
#include "cpu/reference_renderer.h"
#include "gpu/gpu_renderer.h"
#include "gpu/vulkan_context.h"
#include "image/image.h"
#include "scene/scene.h"

namespace vkrt::test {

class Gpu : public ::testing::Test {
  public:
    // Destroys the shared context (a later test suite makes a new one); gpu_fixture.cpp calls it when the tests end.
    static void releaseContext();

  protected:
    static void SetUpTestSuite();
    void SetUp() override;
    void TearDown() override;
    static const VulkanContext& context();

    // One of the project's own scenes (scenes/NAME), its BVH and its first camera for an aspect ratio.
    struct SceneUnderTest {
        Scene scene;
        FlatBvh bvh;
        Camera camera;
    };
    static SceneUnderTest ownScene(const char* name, double aspect);

    // A GPU render with the tests' shader cache; `report`, when given, receives the renderer's report.
    static RenderResult renderGpu(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                                  const RenderSettings& settings, GpuRenderOptions options = {},
                                  GpuRenderReport* report = nullptr, StopCondition stop = {});

  private:
    static inline std::unique_ptr<VulkanContext> context_;
    uint32_t messagesBefore_ = 0;
};

// GPU against the CPU reference with the same seed, within the thresholds of support/reference_comparison.h
// (at least 99.5% of pixels within 1%, mean relative error at most 0.2%); on failure both images and their
// difference are saved for inspection under NAME.
void expectMatchesReference(const Image& gpu, const Image& cpu, const std::string& name);

}  // namespace vkrt::test
