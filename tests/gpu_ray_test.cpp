// The GPU traversal against the CPU's: 30,000 rays per mesh (procedural meshes, analytic spheres from 1e-3
// to 1e3 in radius, analytic shapes and CSG objects under affine maps, real models), and the GPU's random
// numbers against their C++ definition bit for bit.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "cpu/closest_hit.h"
#include "cpu/triangle_intersection.h"
#include "gpu/compute_pipeline.h"
#include "gpu/gpu_raycaster.h"
#include "gpu/scene_features.h"
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

std::string text(glm::vec3 v) {
    char buffer[96];
    std::snprintf(buffer, sizeof(buffer), "(%.9g, %.9g, %.9g)", v.x, v.y, v.z);
    return buffer;
}

// |cos| of the angle between a ray and the surface's normal at the CPU's hit on a triangle or a solid (1 on a
// sphere or a miss).
double surfaceCosine(const Scene& scene, const SurfaceHit& hit, const RayT<double>& ray) {
    if (hit.primitive == kNoPrimitive || scene.isSphere(hit.primitive)) return 1.0;
    if (scene.isTriangle(hit.primitive)) {
        const Triangle& t = scene.triangles[hit.primitive];
        const glm::dvec3 normal = glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0));
        return std::abs(glm::dot(glm::normalize(normal), glm::normalize(ray.direction)));
    }
    const Shape& shape = scene.shapes[static_cast<uint32_t>(hit.u)];
    const shading::ShapePoint p =
        shading::shapePoint(shape.type, static_cast<uint32_t>(hit.v) / 2u, false,
                            shading::affineRows(shape.toObject), ray.origin, ray.direction, hit.t);
    return std::abs(glm::dot(p.normal, glm::normalize(ray.direction)));
}

// The GPU's closest and any hits against the CPU's. Distances agree; a different primitive is allowed only in
// a tie (at most 1 hit in 10,000), a hit against a miss never. Hits on solids carry the shape and face
// crossed (u: the scene's shape, v: face * 2 + flip), integers that must be the CPU's too, except where the
// two legitimately part at an edge between faces: at most 1 hit on a solid in 10,000, the ties' allowance.
// When `minSolidFaces` is given, the rays must have seen at least that many distinct (shape, face, flip)
// triples: every face the test claims to cover. The rays aim at the scene's bounds, or at `aim`.
void expectRaysMatchCpu(const VulkanContext& context, const Scene& scene, const char* name,
                        size_t minSolidFaces = 0, std::optional<Aabb> aim = std::nullopt,
                        double tieAllowance = 1e-4) {
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster raycaster(context, scene, bvh, test::shaderCacheDir());
    const std::vector<gpu::GpuRay> rays = testRays(aim ? *aim : scene.bounds, 30000);
    const std::vector<gpu::GpuHit> closest = raycaster.trace(rays, RaycastMode::Closest);
    const std::vector<gpu::GpuHit> any = raycaster.trace(rays, RaycastMode::Any);
    const double sceneSize = glm::length(scene.bounds.extent());
    size_t samePrimitive = 0, ties = 0, hitMissDisagreements = 0, occlusionDisagreements = 0, hits = 0;
    size_t solidHits = 0, faceDisagreements = 0, distanceErrors = 0;
    size_t distanceErrorsByShape[4] = {};  // by VKRT_SHAPE_*
    std::string someTies;
    std::set<std::pair<uint32_t, uint32_t>> solidFaces;
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
            // very close to the origin; a different triangle is allowed only at the same distance. On the same
            // triangle or solid, the distance is measured along the surface's normal: a grazing ray's hit moves
            // along the ray by the rounding over the cosine (on an NVIDIA GPU, 3e-5 at t = 2.3 on a Duck
            // triangle at cosine 0.0024, 8e-8 from the plane), and the float shape of a solid lies a few ulps
            // from the double one.
            const double cosine = surfaceCosine(scene, cpu, ray);
            const double error = std::abs(static_cast<double>(closest[i].t) - tMax) *
                                 (closest[i].primitive == cpu.primitive ? cosine : 1.0);
            const bool off = error > 1e-5 * tMax + 1e-6 * sceneSize;
            if (off && scene.isSolid(cpu.primitive))
                ++distanceErrorsByShape[scene.shapes[static_cast<uint32_t>(cpu.u)].type];
            if (off && ++distanceErrors <= 3) {
                ADD_FAILURE() << name << " ray " << i << ": GPU t " << closest[i].t << ", CPU t " << tMax
                              << ", cosine " << cosine << "; CPU primitive " << cpu.primitive << " (" << cpu.u
                              << ", " << cpu.v << "), GPU " << closest[i].primitive << " (" << closest[i].u
                              << ", " << closest[i].v << "); origin " << text(rays[i].origin)
                              << ", direction " << text(rays[i].direction);
            }
            if (closest[i].primitive == cpuTriangle) {
                ++samePrimitive;
            } else if (++ties <= 3) {
                char tie[160];
                std::snprintf(tie, sizeof(tie),
                              "; ray %zu at t %.6g: CPU primitive %u (%g, %g), GPU %u (%g, %g)", i, tMax,
                              cpu.primitive, cpu.u, cpu.v, closest[i].primitive, closest[i].u, closest[i].v);
                someTies += tie;
            }
            if (closest[i].primitive == cpuTriangle && scene.isSolid(cpuTriangle)) {
                ++solidHits;
                const auto cpuFace =
                    std::make_pair(static_cast<uint32_t>(cpu.u), static_cast<uint32_t>(cpu.v));
                const auto gpuFace =
                    std::make_pair(static_cast<uint32_t>(closest[i].u), static_cast<uint32_t>(closest[i].v));
                // Integers, exactly: a fraction would be a bug of its own.
                ASSERT_EQ(static_cast<float>(gpuFace.first), closest[i].u) << name << " ray " << i;
                ASSERT_EQ(static_cast<float>(gpuFace.second), closest[i].v) << name << " ray " << i;
                solidFaces.insert(cpuFace);
                if (cpuFace != gpuFace) {
                    ++faceDisagreements;
                    std::printf(
                        "%s ray %zu: t %.9g, CPU shape %u face %u flip %u, GPU shape %u face %u flip %u\n",
                        name, i, tMax, cpuFace.first, cpuFace.second / 2, cpuFace.second % 2, gpuFace.first,
                        gpuFace.second / 2, gpuFace.second % 2);
                }
            }
        }
        if ((any[i].primitive != VKRT_NO_HIT) != cpuHit) ++occlusionDisagreements;
    }
    ASSERT_GT(hits, rays.size() / 4) << name;
    const double agreeing = static_cast<double>(samePrimitive) / static_cast<double>(hits);
    EXPECT_GE(agreeing, 1.0 - tieAllowance)
        << name << ": " << ties << " ties, " << hitMissDisagreements << " hit/miss" << someTies;
    EXPECT_EQ(hitMissDisagreements, 0u) << name << ": every mismatch must be a tie";
    std::printf(
        "%s: %zu rays, %zu hits, %zu ties, %zu hit/miss, %zu occlusion disagreements, %zu distances off",
        name, rays.size(), hits, ties, hitMissDisagreements, occlusionDisagreements, distanceErrors);
    if (solidHits > 0) {
        std::printf(", %zu hits on solids over %zu faces, %zu on another face", solidHits, solidFaces.size(),
                    faceDisagreements);
        if (distanceErrors > 0) {
            std::printf(" (distances off on spheres, boxes, cylinders, cones: %zu, %zu, %zu, %zu)",
                        distanceErrorsByShape[0], distanceErrorsByShape[1], distanceErrorsByShape[2],
                        distanceErrorsByShape[3]);
        }
    }
    std::printf("\n");
    EXPECT_LE(occlusionDisagreements, rays.size() / 10000) << name;
    EXPECT_EQ(distanceErrors, 0u) << name << ": hits at another distance (the first three are listed above)";
    EXPECT_LE(faceDisagreements, solidHits / 10000) << name << ": hits on another shape or face";
    EXPECT_GE(solidFaces.size(), minSolidFaces) << name << ": faces seen";
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
    // Spheres from 1e-2 to 3 in radius beside triangles, then with one of 1e3 and one of 1e-3, one far from
    // the rest: the GPU's roots (shaders/sphere_geometry.h) in float, then in double where the device has it,
    // against the CPU's in double, through the shared BVH.
    std::vector<Sphere> spheres;
    uint32_t state = 12345u;
    auto next = [&] { return static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) * 0x1p-24f; };
    for (int i = 0; i < 400; ++i) {
        const float radius = std::pow(10.0f, -2.0f + 2.5f * next());
        spheres.push_back({glm::vec3(next(), next(), next()) * 4.0f - 2.0f, radius, 0});
    }
    // Within 1024 times of each other in width they are found in float (scene_features.cpp).
    const Scene oneScale = sceneOf(makeTriangleSoup(2000, 4, 0.1f), spheres);
    EXPECT_FALSE(detectFeatures(oneScale).largeSpheres);
    expectRaysMatchCpu(context(), oneScale, "spheres and triangles, in float");
    spheres.push_back({{0.0f, -1003.0f, 0.0f}, 1000.0f, 0});  // a huge sphere as the ground: in double
    spheres.push_back({{0.5f, 0.5f, 0.5f}, 1e-3f, 0});
    const Scene scales = sceneOf(makeTriangleSoup(2000, 4, 0.1f), spheres);
    EXPECT_TRUE(detectFeatures(scales).largeSpheres);
    expectRaysMatchCpu(context(), scales, "spheres and triangles");
}

// Placements of the canonical shapes: translation, then a turn by `degrees` about `axis`, then a non-uniform
// scale (applied first).
glm::dmat4 placed(glm::dvec3 translation, double degrees, glm::dvec3 axis, glm::dvec3 scale) {
    return glm::translate(glm::dmat4(1.0), translation) *
           glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(axis)) *
           glm::scale(glm::dmat4(1.0), scale);
}

// A shear: x += a y, z += b x (GLM's matrices are column-major: column j is the image of axis j).
glm::dmat4 shear(double a, double b) {
    glm::dmat4 m(1.0);
    m[1][0] = a;
    m[0][2] = b;
    return m;
}

bool in(uint32_t state, int shape) {
    return ((state >> shape) & 1u) != 0u;
}

// A solid of test: its shapes (in the unit's frame) and truth table, and how many (shape, face, flip) triples
// random rays are sure to see on it.
struct TestSolid {
    const char* name;
    std::vector<Shape> shapes;
    std::array<uint32_t, 8> table;
    size_t faces;
};

// Each canonical shape under a non-uniform scale and a turn, two with a shear and one mirrored; the classic
// CSG objects (a box minus an off-centre sphere, a lens of two spheres under a non-uniform scale, a sphere
// drilled by two cylinders) and a union of unions within a difference.
std::vector<TestSolid> testSolids() {
    const std::array<uint32_t, 8> alone = truthTable(1, [](uint32_t s) { return in(s, 0); });
    const glm::dmat4 unit(1.0);
    std::vector<TestSolid> solids = {
        {"ellipsoid",
         {makeShape(VKRT_SHAPE_SPHERE, 0, placed({0.3, -0.2, 0.1}, 35.0, {1, 2, 0.5}, {0.9, 0.4, 0.6}))},
         alone,
         1},
        {"box",
         {makeShape(VKRT_SHAPE_BOX, 0, placed({0.1, 0.2, -0.3}, 50.0, {0.3, 1, -0.4}, {1.2, 0.3, 0.7}))},
         alone,
         6},
        {"cylinder",
         {makeShape(VKRT_SHAPE_CYLINDER, 0, placed({-0.2, 0.1, 0.2}, 70.0, {1, 0.2, 0.3}, {0.5, 1.1, 0.3}))},
         alone,
         3},
        {"cone",
         {makeShape(VKRT_SHAPE_CONE, 0, placed({0.0, 0.3, 0.1}, -40.0, {0.2, 0.5, 1}, {0.8, 0.9, 0.4}))},
         alone,
         2},
        {"sheared cylinder",
         {makeShape(VKRT_SHAPE_CYLINDER, 0,
                    placed({0.2, 0.0, 0.1}, 20.0, {0, 0, 1}, {1, 1, 1}) * shear(0.6, 0.3) *
                        glm::scale(unit, {0.4, 0.8, 0.5}))},
         alone,
         3},
        {"sheared, mirrored cone",
         {makeShape(VKRT_SHAPE_CONE, 0,
                    placed({0.0, 0.0, 0.0}, 60.0, {1, 1, 0}, {1, 1, 1}) * shear(-0.5, 0.4) *
                        glm::scale(unit, {-0.7, 0.8, 0.5}))},
         alone,
         2},
    };
    const glm::dmat4 frame = placed({0.1, -0.1, 0.2}, 30.0, {0.2, 1, 0.1}, {0.7, 0.7, 0.7});
    solids.push_back({"box minus sphere",
                      {makeShape(VKRT_SHAPE_BOX, 0, frame),
                       makeShape(VKRT_SHAPE_SPHERE, 0,
                                 frame * placed({0.2, 0.1, 0.0}, 0.0, {0, 1, 0}, {1.25, 1.25, 1.25}))},
                      truthTable(2, [](uint32_t s) { return in(s, 0) && !in(s, 1); }),
                      7});
    const glm::dmat4 lens = placed({0.0, 0.2, 0.0}, 25.0, {1, 0.3, 0}, {1.0, 0.8, 1.2});
    solids.push_back(
        {"lens (two spheres' intersection)",
         {makeShape(VKRT_SHAPE_SPHERE, 0, lens * placed({0, 0, -0.8}, 0.0, {0, 1, 0}, {1.5, 1.5, 1.5})),
          makeShape(VKRT_SHAPE_SPHERE, 0, lens * placed({0, 0, 0.8}, 0.0, {0, 1, 0}, {1.5, 1.5, 1.5}))},
         truthTable(2, [](uint32_t s) { return in(s, 0) && in(s, 1); }),
         2});
    const glm::dmat4 drilled = placed({0.0, 0.0, 0.0}, 15.0, {0, 0, 1}, {0.85, 0.85, 0.85});
    solids.push_back({"sphere minus two cylinders",
                      {makeShape(VKRT_SHAPE_SPHERE, 0, drilled),
                       makeShape(VKRT_SHAPE_CYLINDER, 0, drilled * glm::scale(unit, {0.35, 1.4, 0.35})),
                       makeShape(VKRT_SHAPE_CYLINDER, 0,
                                 drilled * placed({0, 0.1, 0}, 90.0, {1, 0, 0.3}, {0.25, 1.4, 0.25}))},
                      truthTable(3, [](uint32_t s) { return in(s, 0) && !in(s, 1) && !in(s, 2); }),
                      3});
    // (box | cylinder) - (sphere | cone): a union as the first operand and one subtracted.
    solids.push_back(
        {"(box | cylinder) - (sphere | cone)",
         {makeShape(VKRT_SHAPE_BOX, 0, placed({0, 0, 0}, 20.0, {0, 1, 0}, {0.8, 0.5, 0.6})),
          makeShape(VKRT_SHAPE_CYLINDER, 0, placed({0.5, 0, 0}, 80.0, {1, 0, 0.2}, {0.4, 1.0, 0.4})),
          makeShape(VKRT_SHAPE_SPHERE, 0, placed({-0.6, 0.4, 0.3}, 0.0, {0, 1, 0}, {0.5, 0.5, 0.5})),
          makeShape(VKRT_SHAPE_CONE, 0, placed({0.2, 0.6, -0.2}, 10.0, {0, 0, 1}, {0.3, 0.5, 0.3}))},
         truthTable(4, [](uint32_t s) { return (in(s, 0) || in(s, 1)) && !(in(s, 2) || in(s, 3)); }),
         8});
    return solids;
}

Scene solidScene(const std::vector<TestSolid>& solids, const std::vector<Triangle>& triangles = {}) {
    Scene scene;
    scene.materials.push_back(Material{});
    for (const Triangle& t : triangles) addFlatTriangle(scene, t.v0, t.v1, t.v2, 0);
    for (const TestSolid& solid : solids) addSolid(scene, solid.shapes, solid.table);
    finalizeScene(scene);
    return scene;
}

TEST_F(Gpu, RaysMatchCpuOnShapesAndCsgObjects) {
    // 30,000 rays per solid: the float walk of shaders/shape_geometry.h against the double one, faces
    // included.
    for (const TestSolid& solid : testSolids())
        expectRaysMatchCpu(context(), solidScene({solid}), solid.name, solid.faces);
}

TEST_F(Gpu, RaysMatchCpuOnShapesAndCsgObjectsAmongTriangles) {
    // Every solid of the test above, spread over a cube of side 6 among 3,000 triangles, in one BVH.
    std::vector<TestSolid> solids = testSolids();
    for (size_t i = 0; i < solids.size(); ++i) {
        const glm::dmat4 spread = glm::translate(
            glm::dmat4(1.0),
            glm::dvec3(-2.0 + 2.0 * (i % 3), -2.0 + 2.0 * ((i / 3) % 3), -1.0 + 2.0 * (i / 9)));
        for (Shape& shape : solids[i].shapes)
            shape = makeShape(shape.type, 0, spread * glm::dmat4(shape.toWorld));
    }
    std::vector<Triangle> soup = makeTriangleSoup(3000, 6, 0.03f);
    for (Triangle& t : soup) {
        for (glm::vec3* v : {&t.v0, &t.v1, &t.v2}) *v = 6.0f * *v - 3.0f;
    }
    expectRaysMatchCpu(context(), solidScene(solids, soup), "solids among triangles", 41);
}

TEST_F(Gpu, RaysMatchCpuOnTheCsgScene) {
    // scenes/csg.gltf through the loader: the floor's two triangles and every shape and CSG object of the
    // scene, the rays aimed at the solids. They see 26 faces: the 30 of the scene's solids less the four
    // bottom faces that lie on the floor, where the floor (the smaller primitive index) wins the tie, also
    // for rays that start inside a solid and meet such a face and the floor, stored in float about 3e-8
    // apart, a few hundredths of a unit away (the tie's width is relative to |origin| + t, not to t alone).
    const Scene scene = loadGltf((test::sourceDir() / "scenes/csg.gltf").string());
    Aabb solids;
    for (const Solid& solid : scene.solids) solids.grow(solid.bounds);
    expectRaysMatchCpu(context(), scene, "csg.gltf", 26, solids);
}

TEST_F(Gpu, SurfacesCloserThanTheRaysPrecisionAreTies) {
    // Two parallel squares, the lower (triangles 0 and 1) `gap` below the upper (2 and 3), under rays coming
    // down from 0.05 above them with origins `offset` (give or take 0.5) along x. A tie's width is
    // VKRT_TIE_EPSILON (about 1e-6) times |origin| + t: surfaces closer than that are ties, which the smaller
    // index (the lower square) wins on both devices; farther apart, the nearer (upper) one wins. The widths
    // here are 1.5e-6 to 2.5e-6 at offset 2 and about 1e-3 at 1000, while the distance travelled is 0.05: a
    // width relative to the distance alone (5e-8) would take the first case for no tie.
    struct Case {
        double offset, gap;
        bool tie;
    };
    for (const Case c : {Case{2.0, 5e-7, true}, Case{2.0, 1e-4, false}, Case{1000.0, 1e-4, true},
                         Case{1000.0, 5e-3, false}}) {
        const float x0 = static_cast<float>(c.offset) - 1.0f, x1 = static_cast<float>(c.offset) + 1.0f;
        const float top = static_cast<float>(c.gap);
        const Scene scene = sceneOf({{{x0, 0, -1}, {x1, 0, -1}, {x1, 0, 1}, 0},
                                     {{x0, 0, -1}, {x1, 0, 1}, {x0, 0, 1}, 0},
                                     {{x0, top, -1}, {x1, top, -1}, {x1, top, 1}, 0},
                                     {{x0, top, -1}, {x1, top, 1}, {x0, top, 1}, 0}});
        const FlatBvh bvh = bvhFor(scene);
        GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
        std::vector<gpu::GpuRay> rays;
        for (int i = 0; i < 64; ++i) {
            for (int j = 0; j < 64; ++j) {
                const glm::vec3 origin(static_cast<float>(c.offset + (i + 0.37) / 64.0 - 0.5), 0.05f,
                                       static_cast<float>((j + 0.61) / 64.0 - 0.5));
                const glm::vec3 direction = glm::normalize(
                    glm::vec3(0.01f * static_cast<float>(i % 7), -1.0f, 0.01f * static_cast<float>(j % 5)));
                rays.push_back({origin, 0.0f, direction, 1e30f});
            }
        }
        const std::vector<gpu::GpuHit> gpuHits = raycaster.trace(rays, RaycastMode::Closest);
        size_t gpuLower = 0, cpuLower = 0, misses = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            SurfaceHit cpu;
            closestHit(scene, bvh, {glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)}, 1e30,
                       kNoPrimitive, cpu);
            misses += (cpu.primitive == kNoPrimitive) + (gpuHits[i].primitive == VKRT_NO_HIT);
            cpuLower += cpu.primitive < 2u;
            gpuLower += gpuHits[i].primitive < 2u;
        }
        const size_t expected = c.tie ? rays.size() : 0u;
        EXPECT_EQ(misses, 0u) << "offset " << c.offset << ", gap " << c.gap;
        EXPECT_EQ(cpuLower, expected) << "CPU: offset " << c.offset << ", gap " << c.gap;
        EXPECT_EQ(gpuLower, expected) << "GPU: offset " << c.offset << ", gap " << c.gap;
    }
}

TEST_F(Gpu, TiesAreJudgedAgainstTheNearestHitInAnyWalkOrder) {
    // Three parallel squares `gap` apart, the nearest (triangles 4 and 5) at z = 0, the middle (2, 3) at -gap
    // and the farthest (0, 1) at -2 gap, under rays coming down from z = 10: a tie's width there is about
    // VKRT_TIE_EPSILON * 20, and the gaps are 0.6 to 0.8 of it, so the middle square ties with the nearest
    // and the farthest does not. The middle one wins (the smallest index within a tie's width of the nearest
    // hit), whatever order the walk meets them in: the built trees, and one leaf holding the six triangles in
    // either order. Before, each new best hit moved the window to its own distance, so ties chained: the
    // built tree gave the farthest square (1.2 to 1.6 ties' widths behind the nearest), one leaf the nearest.
    const float width = static_cast<float>(VKRT_TIE_EPSILON * 20.0);
    for (const float share : {0.6f, 0.7f, 0.8f}) {
        const float gap = share * width;
        std::vector<Triangle> triangles;
        for (const float z : {-2.0f * gap, -gap, 0.0f}) {
            triangles.push_back({{-1, -1, z}, {1, -1, z}, {1, 1, z}, 0});
            triangles.push_back({{-1, -1, z}, {1, 1, z}, {-1, 1, z}, 0});
        }
        const Scene scene = sceneOf(triangles);
        auto oneLeaf = [&](bool reversed) {
            FlatBvh bvh;
            bvh.nodes.push_back({scene.bounds.min, 0u, scene.bounds.max, 6u});
            for (uint32_t i = 0; i < 6; ++i) bvh.primIndices.push_back(reversed ? 5 - i : i);
            return bvh;
        };
        const std::pair<const char*, FlatBvh> trees[] = {
            {"built", bvhFor(scene)}, {"one leaf", oneLeaf(false)}, {"one leaf, reversed", oneLeaf(true)}};
        std::vector<gpu::GpuRay> rays;
        for (int i = 0; i < 32; ++i) {
            for (int j = 0; j < 32; ++j) {
                const glm::vec3 origin((i + 0.37f) / 32.0f - 0.5f, (j + 0.61f) / 32.0f - 0.5f, 10.0f);
                const glm::vec3 direction = glm::normalize(
                    glm::vec3(0.002f * static_cast<float>(i % 7), 0.002f * static_cast<float>(j % 5), -1.0f));
                rays.push_back({origin, 0.0f, direction, 1e30f});
            }
        }
        for (const auto& [name, bvh] : trees) {
            GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
            const std::vector<gpu::GpuHit> gpuHits = raycaster.trace(rays, RaycastMode::Closest);
            size_t cpuMiddle = 0, gpuMiddle = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                SurfaceHit cpu;
                closestHit(scene, bvh, {glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)}, 1e30,
                           kNoPrimitive, cpu);
                cpuMiddle += cpu.primitive == 2u || cpu.primitive == 3u;
                gpuMiddle += gpuHits[i].primitive == 2u || gpuHits[i].primitive == 3u;
            }
            EXPECT_EQ(cpuMiddle, rays.size()) << "CPU, " << name << ", gap " << share << " of a tie";
            EXPECT_EQ(gpuMiddle, rays.size()) << "GPU, " << name << ", gap " << share << " of a tie";
        }
    }
}

TEST_F(Gpu, AxisParallelRaysFromABoxFaceHit) {
    // A square (two triangles) across [corner, corner + size] in two axes, at `size` * 5 along the third, and
    // rays parallel to that third axis from a grid of points over the square's closed extent, its edges
    // included, going towards it: every ray meets the square (edges count), so every box on the way holds
    // the ray's origin on a face where the ray's direction is zero in that axis. The GPU's slab test took
    // 1 / 0 as a finite 1e30, so an origin on a box's upper face gave (upper - origin) * 1e30 = 0 as the
    // slab's exit: the rays along the square's upper edges missed it (CPU: hit). At 1e7 from the origin the
    // coordinates are whole numbers, where a model's boxes fall on its vertices.
    for (const float corner : {0.0f, 1e7f, -3.5f}) {
        for (int axis = 0; axis < 3; ++axis) {
            for (const float sign : {1.0f, -1.0f}) {
                const int a = (axis + 1) % 3, b = (axis + 2) % 3;
                const float size = corner == 1e7f ? 4.0f : 1.0f;
                auto point = [&](float pa, float pb, float along) {
                    glm::vec3 p;
                    p[a] = pa;
                    p[b] = pb;
                    p[axis] = along;
                    return p;
                };
                const float lo = corner, hi = corner + size, plane = sign * 5.0f * size;
                const Scene scene =
                    sceneOf({{point(lo, lo, plane), point(hi, lo, plane), point(hi, hi, plane), 0},
                             {point(lo, lo, plane), point(hi, hi, plane), point(lo, hi, plane), 0}});
                const FlatBvh bvh = bvhFor(scene);
                GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
                std::vector<gpu::GpuRay> rays;
                glm::vec3 direction(0.0f);
                direction[axis] = sign;
                for (int i = 0; i <= 8; ++i) {
                    for (int j = 0; j <= 8; ++j) {
                        rays.push_back({point(lo + size * static_cast<float>(i) / 8.0f,
                                              lo + size * static_cast<float>(j) / 8.0f, 0.0f),
                                        0.0f, direction, 1e30f});
                    }
                }
                const std::vector<gpu::GpuHit> closest = raycaster.trace(rays, RaycastMode::Closest);
                const std::vector<gpu::GpuHit> any = raycaster.trace(rays, RaycastMode::Any);
                size_t cpuMisses = 0, gpuMisses = 0, gpuOcclusionMisses = 0;
                std::string firstMiss;
                for (size_t i = 0; i < rays.size(); ++i) {
                    SurfaceHit cpu;
                    cpuMisses += !closestHit(scene, bvh, {glm::dvec3(rays[i].origin), glm::dvec3(direction)},
                                             1e30, kNoPrimitive, cpu);
                    gpuOcclusionMisses += any[i].primitive == VKRT_NO_HIT;
                    if (closest[i].primitive == VKRT_NO_HIT && gpuMisses++ == 0)
                        firstMiss = "; the first from " + text(rays[i].origin);
                }
                const std::string name = "corner " + std::to_string(corner) + ", axis " +
                                         std::to_string(axis) + (sign > 0.0f ? " +" : " -");
                EXPECT_EQ(cpuMisses, 0u) << name;
                EXPECT_EQ(gpuMisses, 0u) << name << firstMiss;
                EXPECT_EQ(gpuOcclusionMisses, 0u) << name;
            }
        }
    }
}

TEST_F(Gpu, ShapeHitsKeepTheirPrecisionFarAway) {
    // Each canonical shape (under a turn and a mild non-uniform scale) hit by 20,000 rays from 4, 32, 256 and
    // 2048 units away, aimed at points of its inner part: the float distance stays within 1e-5 relative of
    // the double one along the normal (as spheres' and triangles' do, the stable quadrics of
    // sphere_geometry.h), and no ray that meets the surface at more than 6 degrees from grazing misses. The
    // distance in object units is what counts: a cone a hundredth of a unit high seen from 2.56 units is the
    // same as this one from 256.
    const std::array<uint32_t, 8> alone = truthTable(1, [](uint32_t s) { return in(s, 0); });
    const glm::dmat4 map = placed({0.0, 0.0, 0.0}, 30.0, {1, 1, 0}, {1.0, 0.8, 1.2});
    for (const uint32_t type : {VKRT_SHAPE_SPHERE, VKRT_SHAPE_BOX, VKRT_SHAPE_CYLINDER, VKRT_SHAPE_CONE}) {
        Scene scene;
        scene.materials.push_back(Material{});
        addSolid(scene, {makeShape(type, 0, map)}, alone);
        finalizeScene(scene);
        const FlatBvh bvh = bvhFor(scene);
        GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
        for (const float distance : {4.0f, 32.0f, 256.0f, 2048.0f}) {
            std::vector<gpu::GpuRay> rays;
            for (uint32_t i = 0; i < 20000; ++i) {
                auto r = [&](uint32_t d) { return vkrtRandom(7, i, 0, d) * 2.0f - 1.0f; };
                // Directions uniform over the cube's surface's directions, targets inside the shape's core
                // (the cone's core is its lower half: its inscribed points near the axis).
                const glm::vec3 direction = glm::normalize(glm::vec3(r(0), r(1), r(2)));
                const glm::vec3 core = type == VKRT_SHAPE_CONE
                                           ? glm::vec3(0.3f * r(3), -0.5f + 0.4f * r(4), 0.3f * r(5))
                                           : 0.5f * glm::vec3(r(3), r(4), r(5));
                const glm::vec3 target(map * glm::dvec4(core, 1.0));
                rays.push_back({target - distance * direction, 0.0f, direction, 1e30f});
            }
            const std::vector<gpu::GpuHit> hits = raycaster.trace(rays, RaycastMode::Closest);
            size_t compared = 0, misses = 0, far = 0;
            double sum = 0.0, worst = 0.0;
            for (size_t i = 0; i < rays.size(); ++i) {
                const RayT<double> ray{glm::dvec3(rays[i].origin), glm::dvec3(rays[i].direction)};
                SurfaceHit cpu;
                ASSERT_TRUE(closestHit(scene, bvh, ray, 1e30, kNoPrimitive, cpu)) << "every ray aims inside";
                const double cosine = surfaceCosine(scene, cpu, ray);
                if (cosine < 0.1) continue;  // grazing: the float and double surfaces may part
                ++compared;
                if (hits[i].primitive == VKRT_NO_HIT) {
                    ++misses;
                    continue;
                }
                const double error = std::abs(static_cast<double>(hits[i].t) - cpu.t) * cosine / cpu.t;
                sum += error;
                worst = std::max(worst, error);
                if (error > 1e-5) ++far;
            }
            std::printf(
                "shape %u from %g: %zu rays compared, %zu misses, %zu off by more than 1e-5 relative; "
                "relative error mean %.3g, worst %.3g\n",
                type, distance, compared, misses, far, sum / static_cast<double>(compared), worst);
            EXPECT_EQ(misses, 0u) << "shape " << type << " from " << distance;
            EXPECT_EQ(far, 0u) << "shape " << type << " from " << distance << ": worst " << worst;
        }
    }
}

TEST_F(Gpu, RepeatedTracesInOneSubmissionGiveTheSameHits) {
    // ray_benchmark's timing on GPUs: the batch traced several times back to back; the hits are a single
    // trace's, and the times are per trace: eight traces divided by eight take about one trace's time, where
    // a single trace divided by eight would take an eighth.
    const Scene scene = sceneOf(makeUvSphere(glm::vec3(0.2f), 1.3f, 30, 60));
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster raycaster(context(), scene, bvh, test::shaderCacheDir());
    const std::vector<gpu::GpuRay> rays = testRays(scene.bounds, 65536);
    for (const RaycastMode mode : {RaycastMode::Closest, RaycastMode::Any}) {
        raycaster.trace(rays, mode);  // lavapipe compiles the kernel at its first dispatch
        RaycastTiming once, eight;
        const std::vector<gpu::GpuHit> a = raycaster.trace(rays, mode, &once),
                                       b = raycaster.trace(rays, mode, &eight, 8);
        size_t hits = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(gpu::GpuHit)), 0) << "ray " << i;
            hits += a[i].primitive != VKRT_NO_HIT;
        }
        EXPECT_GT(hits, rays.size() / 4);
        std::printf("one trace: %.3f ms of GPU time, %.3f ms wall; per trace of eight: %.3f and %.3f\n",
                    once.gpuMs, once.wallMs, eight.gpuMs, eight.wallMs);
        if (once.gpuMs > 0.0) {
            EXPECT_GT(eight.gpuMs, 0.4 * once.gpuMs);  // 0.125 if the repeats were lost
        }
        EXPECT_GT(eight.wallMs, 0.4 * once.wallMs);
    }
}

TEST_F(Gpu, SpreadWorkgroupsTraceEveryRayOnce) {
    // 10,001 rays: 157 blocks of 64, the last part full, each traced by another workgroup than in order.
    const Scene scene = sceneOf(makeUvSphere(glm::vec3(0.2f), 1.3f, 30, 60));
    const FlatBvh bvh = bvhFor(scene);
    GpuRaycaster inOrder(context(), scene, bvh, test::shaderCacheDir(), {}, WorkgroupOrder::InOrder);
    GpuRaycaster spread(context(), scene, bvh, test::shaderCacheDir(), {}, WorkgroupOrder::Spread);
    const std::vector<gpu::GpuRay> rays = testRays(scene.bounds, 10001);
    for (const RaycastMode mode : {RaycastMode::Closest, RaycastMode::Any}) {
        const std::vector<gpu::GpuHit> a = inOrder.trace(rays, mode), b = spread.trace(rays, mode);
        size_t hits = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(a[i].primitive, b[i].primitive) << "ray " << i;
            ASSERT_EQ(a[i].t, b[i].t) << "ray " << i;
            hits += a[i].primitive != VKRT_NO_HIT;
        }
        EXPECT_GT(hits, rays.size() / 4);
    }
    const bool cpuDevice = context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    EXPECT_EQ(GpuRaycaster(context(), scene, bvh, test::shaderCacheDir()).workgroupOrder(),
              cpuDevice ? WorkgroupOrder::Spread : WorkgroupOrder::InOrder);
    // Which workgroup, in launch order, took each block: spread, the k-th of column t took block k * T + t,
    // so that lavapipe's thread t (its run of workgroups the t-th column) takes blocks from the whole range.
    GpuRaycaster recording(context(), scene, bvh, test::shaderCacheDir(), {"VKRT_RECORD_WORKGROUPS"},
                           WorkgroupOrder::Spread);
    const uint32_t blocks =
        (static_cast<uint32_t>(rays.size()) + VKRT_RAYCAST_WORKGROUP - 1) / VKRT_RAYCAST_WORKGROUP;
    const uint32_t threads = spreadThreads(WorkgroupOrder::Spread);
    const SpreadGrid grid = spreadGrid(blocks, threads);
    const std::vector<gpu::GpuHit> launched = recording.trace(rays, RaycastMode::Closest);
    for (size_t i = 0; i < rays.size(); ++i) {
        const uint32_t block = static_cast<uint32_t>(i) / VKRT_RAYCAST_WORKGROUP;
        const uint32_t column = block % grid.columns, k = block / grid.columns;
        ASSERT_EQ(launched[i].t, static_cast<float>(k + grid.perColumn * column))
            << "ray " << i << ", " << threads << " threads";
    }
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
