// The GPU traversal against the CPU's: 30,000 rays per mesh (procedural meshes, analytic spheres from 1e-3
// to 1e3 in radius, real models), and the GPU's random numbers against their C++ definition bit for bit.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/closest_hit.h"
#include "cpu/triangle_intersection.h"
#include "gpu/compute_pipeline.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/shader_compiler.h"
#include "random.h"
#include "scene/gltf_loader.h"
#include "scene/procedural_meshes.h"
#include "scene/scene_builder.h"
#include "support/gpu_fixture.h"
#include "support/render_both.h"
#include "support/test_paths.h"

namespace vkrt {
namespace {

using test::bvhFor;
using test::Gpu;

TEST_F(Gpu, RandomNumbersMatchTheCppDefinitionBitForBit) {
    std::ifstream file(test::sourceDir() / "tests/glsl/random_check.comp");
    std::stringstream source;
    source << file.rdbuf();
    const CompiledShader shader =
        compileShaderSource("random_check.comp", source.str(), {}, test::shaderCacheDir());
    ComputePipeline pipeline(context(), shader.spirv, 1, 16);
    constexpr uint32_t count = 100000, seed = 12345;
    GpuBuffer out(context(), count * 4 * sizeof(uint32_t));
    pipeline.bind({&out});
    const uint32_t constants[4] = {seed, count, 0, 0};
    context().submitAndWait([&](VkCommandBuffer commands) {
        pipeline.dispatch(commands, constants, sizeof(constants), (count + 63) / 64, 1);
        makeShaderWritesVisibleToHost(commands);
    });
    std::vector<uint32_t> words(count * 4);
    out.download(words.data(), words.size() * sizeof(uint32_t));
    auto bitsOf = [](float value) {
        uint32_t bits;
        std::memcpy(&bits, &value, 4);
        return bits;
    };
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t pixel = i * 7919u, sample = i % 1024u, dimension = i % 37u;
        ASSERT_EQ(words[4 * i], vkrtRandomBits(seed, pixel, sample, dimension)) << i;
        ASSERT_EQ(words[4 * i + 1], bitsOf(vkrtRandom(seed, pixel, sample, dimension))) << i;
        ASSERT_EQ(words[4 * i + 2], bitsOf(vkrtStratified(seed, pixel, sample, dimension, 0))) << i;
        ASSERT_EQ(words[4 * i + 3], bitsOf(vkrtStratified(seed, pixel, sample, dimension, 1))) << i;
    }
}

// Rays of three kinds against one mesh: camera-like (from a point outside, towards the mesh), shadow-like
// (between two points near the surface) and incoherent (random origins and directions).
std::vector<gpu::GpuRay> testRays(const Aabb& bounds, int count) {
    std::vector<gpu::GpuRay> rays;
    const glm::vec3 lo = bounds.min, extent = bounds.extent(), center = bounds.center();
    const float radius = glm::length(extent);
    for (int i = 0; i < count; ++i) {
        auto r = [&](uint32_t d) { return vkrtRandom(99, static_cast<uint32_t>(i), 0, d); };
        const glm::vec3 inside = lo + extent * glm::vec3(r(0), r(1), r(2));
        glm::vec3 origin, direction;
        switch (i % 3) {
            case 0:  // camera: from a fixed eye
                origin = center + glm::vec3(0.3f, 0.2f, 1.5f) * radius;
                break;
            case 1:  // shadow: from another point inside the box
                origin = lo + extent * glm::vec3(r(3), r(4), r(5));
                break;
            default:  // incoherent
                origin = center + radius * (glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f);
                break;
        }
        direction = glm::normalize(inside - origin);
        if (!std::isfinite(direction.x)) direction = glm::vec3(0, 0, 1);
        rays.push_back({origin, 0.0f, direction, i % 3 == 1 ? glm::length(inside - origin) : 1e30f});
    }
    return rays;
}

Scene sceneOf(const std::vector<Triangle>& triangles, const std::vector<Sphere>& spheres = {}) {
    Scene scene;
    scene.materials.push_back(Material{});
    for (const Triangle& t : triangles) addFlatTriangle(scene, t.v0, t.v1, t.v2, 0);
    scene.spheres = spheres;
    finalizeScene(scene);
    return scene;
}

void expectRaysMatchCpu(const VulkanContext& context, const Scene& scene, const char* name) {
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster raycaster(context, scene, bvh, test::shaderCacheDir());
    const std::vector<gpu::GpuRay> rays = testRays(scene.bounds, 30000);
    const std::vector<gpu::GpuHit> closest = raycaster.trace(rays, RaycastMode::Closest);
    const std::vector<gpu::GpuHit> any = raycaster.trace(rays, RaycastMode::Any);
    const double sceneSize = glm::length(scene.bounds.extent());
    size_t samePrimitive = 0, ties = 0, hitMissDisagreements = 0, occlusionDisagreements = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
        SurfaceHit cpu;
        closestHit(scene, bvh, ray, rays[i].tMax, kNoPrimitive, cpu);
        const uint32_t cpuTriangle = cpu.primitive;
        const double tMax = cpu.primitive == kNoPrimitive ? rays[i].tMax : cpu.t;
        const bool cpuHit = cpuTriangle != VKRT_NO_HIT, gpuHit = closest[i].primitive != VKRT_NO_HIT;
        hits += cpuHit;
        if (cpuHit != gpuHit) {
            ++hitMissDisagreements;
        } else if (cpuHit) {
            // Distances agree to 1e-5 relative, plus a floor of a few float ulps of the scene's size for hits
            // very close to the origin; a different triangle is allowed only at the same distance.
            ASSERT_NEAR(closest[i].t, tMax, 1e-5 * tMax + 1e-6 * sceneSize) << name << " ray " << i;
            if (closest[i].primitive == cpuTriangle)
                ++samePrimitive;
            else
                ++ties;
        }
        if ((any[i].primitive != VKRT_NO_HIT) != cpuHit) ++occlusionDisagreements;
    }
    ASSERT_GT(hits, rays.size() / 4) << name;
    const double agreeing = static_cast<double>(samePrimitive) / static_cast<double>(hits);
    EXPECT_GE(agreeing, 0.9999) << name << ": " << ties << " ties, " << hitMissDisagreements << " hit/miss";
    EXPECT_EQ(hitMissDisagreements, 0u) << name << ": every mismatch must be a tie";
    std::printf("%s: %zu rays, %zu hits, %zu ties, %zu hit/miss, %zu occlusion disagreements\n", name,
                rays.size(), hits, ties, hitMissDisagreements, occlusionDisagreements);
    EXPECT_LE(occlusionDisagreements, rays.size() / 10000) << name;
}

TEST_F(Gpu, RaysMatchCpuTraversalOnProceduralMeshes) {
    expectRaysMatchCpu(context(), sceneOf(makeUvSphere(glm::vec3(0.2f), 1.3f, 60, 120)), "sphere");
    expectRaysMatchCpu(context(), sceneOf(makeTriangleSoup(20000, 4, 0.1f)), "soup");
    // 20k identical triangles over a large quad, and a huge triangle below: stacks of ties and wide boxes.
    std::vector<Triangle> stack = makeTriangleSoup(2000, 8, 0.3f);
    stack.push_back({{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, 0});
    stack.insert(stack.end(), 20000, Triangle{{0.1f, 0.2f, 0.5f}, {0.9f, 0.2f, 0.5f}, {0.5f, 0.9f, 0.5f}, 0});
    stack.push_back({{-1e5f, -1.0f, -1e5f}, {1e5f, -1.0f, -1e5f}, {0.0f, -1.0f, 1e5f}, 0});
    expectRaysMatchCpu(context(), sceneOf(stack), "identical triangles and a huge one");
}

TEST_F(Gpu, RaysMatchCpuOnAnalyticSpheres) {
    // Spheres from 1e-3 to 1e3 in radius beside triangles, one far from the rest: the float test of
    // shaders/sphere_geometry.h against the double one, through the shared BVH.
    std::vector<Sphere> spheres;
    uint32_t state = 12345u;
    auto next = [&] { return static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
    for (int i = 0; i < 400; ++i) {
        const float radius = std::pow(10.0f, -2.0f + 2.5f * next());
        spheres.push_back({glm::vec3(next(), next(), next()) * 4.0f - 2.0f, radius, 0});
    }
    spheres.push_back({{0.0f, -1003.0f, 0.0f}, 1000.0f, 0});  // a huge sphere as the ground
    spheres.push_back({{0.5f, 0.5f, 0.5f}, 1e-3f, 0});
    expectRaysMatchCpu(context(), sceneOf(makeTriangleSoup(2000, 4, 0.1f), spheres), "spheres and triangles");
}

TEST_F(Gpu, RaysMatchCpuTraversalOnRealModels) {
    if (!test::haveScenesReal()) GTEST_SKIP() << "no " << test::scenesReal();
    for (const char* model : {"khronos-Duck/glTF-Binary/Duck.glb", "khronos-Suzanne/glTF/Suzanne.gltf",
                              "cornell-box-nvidia/cornellBox.gltf"}) {
        expectRaysMatchCpu(context(), loadGltf((test::scenesReal() / model).string()), model);
    }
}

}  // namespace
}  // namespace vkrt
