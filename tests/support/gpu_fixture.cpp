#include "support/gpu_fixture.h"

#include "scene/camera_selection.h"
#include "scene/gltf_loader.h"
#include "support/reference_comparison.h"
#include "support/render_both.h"
#include "support/test_paths.h"

namespace vkrt::test {

namespace {

// The shared context is destroyed when the tests end, before the program's static objects are: a Vulkan device
// that outlives them takes down NVIDIA's driver at exit (every test program crashed there after its tests had
// passed, seen on an H200), and the Vulkan specification promises nothing for objects destroyed that late.
class ReleaseContextAfterTheTests : public ::testing::Environment {
  public:
    void TearDown() override { Gpu::releaseContext(); }
};
[[maybe_unused]] ::testing::Environment* const kReleaseContext =
    ::testing::AddGlobalTestEnvironment(new ReleaseContextAfterTheTests);

}  // namespace

void Gpu::releaseContext() {
    context_.reset();
}

void Gpu::SetUpTestSuite() {
    if (!context_) {
        ContextOptions options;
        options.validation = true;
        context_ = std::make_unique<VulkanContext>(options);
    }
}

void Gpu::SetUp() {
    messagesBefore_ = context_->validationMessages();
}

void Gpu::TearDown() {
    EXPECT_EQ(context_->validationMessages(), messagesBefore_) << "the validation layer reported problems";
}

const VulkanContext& Gpu::context() {
    return *context_;
}

Gpu::SceneUnderTest Gpu::ownScene(const char* name, double aspect) {
    Scene scene = loadGltf((sourceDir() / "scenes" / name).string());
    FlatBvh bvh = bvhFor(scene);
    const Camera camera = selectCamera(scene, 0, aspect);
    return {std::move(scene), std::move(bvh), camera};
}

RenderResult Gpu::renderGpu(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                            const RenderSettings& settings, GpuRenderOptions options,
                            GpuRenderReport* report, StopCondition stop) {
    options.shaderCacheDir = shaderCacheDir();
    GpuRenderer renderer(context(), scene, bvh, camera, settings, options);
    RenderResult result = renderer.render({}, {}, 0.0, stop);
    if (report) *report = renderer.report();
    return result;
}

void expectMatchesReference(const Image& gpu, const Image& cpu, const std::string& name) {
    const ImageDifference d = compareWithReference(gpu, cpu);
    EXPECT_LE(d.fractionOff, kMaxFractionOff) << name << ": " << d.fractionOff * 100 << "% of pixels off";
    EXPECT_LE(d.meanRelativeError, kMaxMeanRelativeError) << name;
    if (!withinReferenceThresholds(d)) saveForInspection(gpu, cpu, name);
}

}  // namespace vkrt::test
