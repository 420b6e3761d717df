// Every shared shading function (shaders/*.h) evaluated on the GPU in single precision and in C++ in double
// precision on the same table of inputs, grazing angles, total internal reflection, roughness 0 and 1 and
// radii from 1e-2 to 1e5 included, compared function by function with stated tolerances. The closed-form
// tests (optics_test.cpp, reference_renderer_test.cpp) check the C++ evaluation; this test carries them over
// to the code the GPU runs.
#include <array>
#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gpu/compute_pipeline.h"
#include "gpu/gpu_buffer.h"
#include "gpu/gpu_timer.h"
#include "gpu/shader_compiler.h"
#include "gpu/vulkan_context.h"
#include "scene/environment_map.h"
#include "support/test_paths.h"
#include "texture_sampling.h"

#include "glsl/shading_cases.h"

namespace vkrt {
namespace {

using shading::FunctionCase;

const char* const kFunctionNames[VKRT_CASE_COUNT] = {"fresnel (dielectric, Schlick, F0)",
                                                     "refraction and reflection",
                                                     "GGX D, Lambda, G1, G2, pdf, alpha",
                                                     "GGX visible-normal sampling",
                                                     "surface response and BRDF",
                                                     "punctual light arrival",
                                                     "triangle light sampling",
                                                     "sphere light sampling and pdf",
                                                     "sphere roots and texture coordinates",
                                                     "Beer-Lambert, pdfs, power heuristic",
                                                     "medium stack",
                                                     "texture sampling, sRGB, wrapping",
                                                     "camera rays",
                                                     "pixel filters, concentric disk",
                                                     "orthonormal basis",
                                                     "rotation, max component",
                                                     "reflected light, diffuse and F0",
                                                     "texture bindings, KHR_texture_transform",
                                                     "environment sampling, lookup and pdf"};

// The CPU's texel fetch for texture_sampling.h, and the test environment map in the same words.
struct TexelDevice {
    const std::vector<uint32_t>* texels;
    uint32_t texel(uint32_t index) const { return (*texels)[index]; }
    double environmentWord(uint32_t i) const {
        return std::bit_cast<float>((*texels)[VKRT_CASE_ENVIRONMENT_FIRST + i]);
    }
    glm::uvec2 environmentSize() const { return {VKRT_CASE_ENVIRONMENT_WIDTH, VKRT_CASE_ENVIRONMENT_HEIGHT}; }
    glm::dvec2 environmentRotation() const { return {VKRT_CASE_ENVIRONMENT_COS, VKRT_CASE_ENVIRONMENT_SIN}; }
    glm::dvec3 environmentTexel(uint32_t i) const {
        return {environmentWord(4 * i), environmentWord(4 * i + 1), environmentWord(4 * i + 2)};
    }
    double environmentColumnCdf(uint32_t i) const { return environmentWord(4 * i + 3); }
    double environmentRowCdf(uint32_t y) const {
        return environmentWord(4 * VKRT_CASE_ENVIRONMENT_WIDTH * VKRT_CASE_ENVIRONMENT_HEIGHT + y);
    }
    gpu::GpuTexture textureInfo(int) const {
        return {0, VKRT_CASE_TEXTURE_WIDTH, VKRT_CASE_TEXTURE_HEIGHT, VKRT_WRAP_REPEAT};
    }
    gpu::GpuTextureBinding textureBinding(int index) const {
        using glm::vec3;
        if (index == 0) return {VKRT_CASE_BINDING0_ROW0, 0, VKRT_CASE_BINDING0_ROW1, VKRT_BINDING_SRGB};
        return {VKRT_CASE_BINDING1_ROW0, 0, VKRT_CASE_BINDING1_ROW1, 0u};
    }
    glm::dvec2 textureCoordinates(uint32_t, glm::dvec2 uv, uint32_t) const { return uv; }
    // The cases look textures up with no footprint (level 0), which never asks for the density.
    double textureDensity(uint32_t, glm::dvec2, uint32_t) const { return 0.0; }
};

// How far single precision may fall from double precision, per result. The relative part is a few hundred
// float ulps (2^-23 = 1.2e-7); the absolute part covers results that cancel to near zero. Results whose
// conditioning varies with the input scale their tolerance by it (see tolerances()).
struct Tolerance {
    double absolute;
    double relative;
};

class ShadingFunctions : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        ContextOptions options;
        options.validation = true;
        context_ = std::make_unique<VulkanContext>(options);
    }
    static void TearDownTestSuite() { context_.reset(); }
    static inline std::unique_ptr<VulkanContext> context_;
};

FunctionCase makeCase(uint32_t function, uint32_t integer, glm::vec4 a, glm::vec4 b = glm::vec4(0.0f),
                      glm::vec4 c = glm::vec4(0.0f), glm::vec4 d = glm::vec4(0.0f),
                      glm::vec4 e = glm::vec4(0.0f)) {
    FunctionCase fc{};
    fc.function = function;
    fc.integer = integer;
    fc.a = a;
    fc.b = b;
    fc.c = c;
    fc.d = d;
    fc.e = e;
    return fc;
}

glm::vec4 direction(double theta, double phi = 0.0) {
    return glm::vec4(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta), 0.0f);
}

std::vector<FunctionCase> makeCases() {
    std::vector<FunctionCase> cases;
    const float roughnesses[] = {0.0f, 1e-3f, 0.1f, 0.5f, 1.0f};
    // Fresnel: normal, oblique and grazing incidence; from outside, from inside (total internal reflection
    // beyond 48 degrees for glass), index-matched and diamond.
    for (float cosI : {1.0f, 0.9f, 0.5f, 0.2f, 1e-4f, 0.0f}) {
        for (float eta : {1.5f, 1.0f / 1.5f, 1.0f, 2.4f, 1.0f / 2.4f}) {
            cases.push_back(makeCase(VKRT_CASE_FRESNEL, 0, {cosI, eta, 0, 0}, {0.9f, 0.6f, 0.05f, 0}));
        }
    }
    for (double theta : {0.0, 0.5, 0.9, 1.2, 1.5707}) {
        for (float eta : {1.5f, 1.0f / 1.5f, 1.0f, 2.4f}) {
            glm::vec4 normal(0, 0, 1, eta);
            cases.push_back(makeCase(VKRT_CASE_REFRACT, 0, direction(theta, 0.3), normal));
        }
    }
    // GGX: from the mirror limit (roughness 1e-3) to roughness 1, half vectors from the normal to grazing.
    for (float roughness : roughnesses) {
        const float alpha = std::max(roughness * roughness, 1e-6f);
        for (float cosH : {1.0f, 0.999f, 0.9f, 0.5f, 0.05f}) {
            cases.push_back(makeCase(VKRT_CASE_GGX, 0, {cosH, alpha, 0.7f, roughness}));
        }
        for (double theta : {0.05, 0.8, 1.5}) {
            for (float u : {0.1f, 0.5f, 0.95f}) {
                glm::vec4 toViewer = direction(theta, 1.0);
                toViewer.w = alpha;
                cases.push_back(makeCase(VKRT_CASE_VISIBLE_NORMAL, 0, toViewer, {u, 1.0f - u * 0.7f, 0, 0}));
            }
        }
        // Surface response: dielectric, metal and glass at this roughness, lights from several directions.
        for (float metallic : {0.0f, 1.0f}) {
            for (float transmission : {0.0f, 1.0f}) {
                for (double lightTheta : {0.3, 1.2}) {
                    for (uint32_t function : {VKRT_CASE_SURFACE, VKRT_CASE_SURFACE_LIGHT}) {
                        for (float specular : {1.0f, 0.4f}) {  // KHR_materials_specular's factor
                            cases.push_back(makeCase(
                                function, 0, {0.8f, 0.5f, 0.2f, metallic}, {2.0f, 1.5f, 1.0f, roughness},
                                {transmission, 1.5f, 0.5f, specular},
                                direction(0.4, 0.2) + glm::vec4(0, 0, 0, 0.8f), direction(lightTheta, 2.9)));
                        }
                    }
                }
            }
        }
    }
    // Punctual lights: point with and without range, spot inside, across and outside its cone, directional.
    for (uint32_t type : {0u, 1u, 2u}) {
        for (float range : {0.0f, 3.0f}) {
            for (glm::vec4 point :
                 {glm::vec4(0, 0, 0, 0), glm::vec4(0.5f, 0.2f, -1, 0), glm::vec4(2, 1, -0.5f, 0)}) {
                cases.push_back(makeCase(VKRT_CASE_PUNCTUAL, type, {0, 0, 2, range}, {0.1f, 0, -1, 0.7f},
                                         {50, 30, 10, 5.0f}, point));
            }
        }
    }
    // A triangle light (area 3.04, picked with probability 0.4) seen from just below it (solid angle 3.9) and
    // from above (0.33), where it looks large and is sampled by solid angle, and from far away (7e-4),
    // farther (7e-6) and its own plane (0), sampled by area; and at scales 1e-12 and 1e12 (an area of 3e-24,
    // whose square underflows in float).
    struct View {
        glm::vec3 from;
        float scale;
    };
    for (const View view :
         {View{{0.4f, 0.6f, 0.8f}, 1.0f}, View{{1.0f, 1.0f, 4.0f}, 1.0f}, View{{30.0f, -20.0f, 50.0f}, 1.0f},
          View{{300.0f, -200.0f, 500.0f}, 1.0f}, View{{-2.0f, 0.0f, 1.0f}, 1.0f},
          View{{0.4f, 0.6f, 0.8f}, 1e-12f}, View{{1.0f, 1.0f, 4.0f}, 1e-12f},
          View{{300.0f, -200.0f, 500.0f}, 1e-12f}, View{{1.0f, 1.0f, 4.0f}, 1e12f}}) {
        const float k = view.scale;
        const glm::vec3 from = k * view.from;
        for (float u : {0.0f, 0.3f, 0.999f}) {
            for (float v : {0.0f, 0.5f, 0.999f}) {
                cases.push_back(makeCase(VKRT_CASE_TRIANGLE_LIGHT, 0, {0, 0, k, 0}, {2 * k, 0, k, 0.4f},
                                         {0, 3 * k, 1.5f * k, from.x}, {u, v, from.y, from.z}));
            }
        }
    }
    // Spheres from 1e-2 to 1e5 in radius, seen from inside, nearby and far away.
    for (float radius : {1e-2f, 1.0f, 1e3f, 1e5f}) {
        for (float distance : {0.5f, 2.0f, 1e3f}) {
            const glm::vec4 center(1, -2, 3, radius);
            const glm::vec4 from =
                glm::vec4(1, -2, 3, 0) + distance * radius * glm::vec4(0.6f, 0.0f, 0.8f, 0.0f);
            for (float u : {0.05f, 0.5f, 0.95f}) {
                cases.push_back(makeCase(VKRT_CASE_SPHERE_LIGHT, 0, center, from + glm::vec4(0, 0, 0, 0.3f),
                                         {u, 1.0f - u, 0, 0}));
            }
            for (glm::vec4 aim : {-glm::vec4(0.6f, 0.0f, 0.8f, 0), glm::vec4(-0.6f, 0.1f, -0.78f, 0),
                                  glm::vec4(0, 1, 0, 0)}) {
                cases.push_back(makeCase(VKRT_CASE_SPHERE, 0, center, from, aim));
            }
        }
    }
    for (float distance : {0.0f, 0.5f, 3.0f, INFINITY}) {
        for (float attenuationDistance : {0.25f, INFINITY}) {
            cases.push_back(makeCase(VKRT_CASE_ABSORPTION, 0, {0.5f, 0.0f, 1.0f, attenuationDistance},
                                     {distance, 0.3f, 2.0f, 0.5f}, {1.0f, 0.4f, 0.9f, 2.5f}));
        }
    }
    for (uint32_t ops : {0x0u, 0x1u, 0x21u, 0x921u, 0xa21u, 0x54321u, 0x87654321u, 0xb9321u}) {
        cases.push_back(makeCase(VKRT_CASE_MEDIA, ops, glm::vec4(0)));
    }
    for (uint32_t flags : {0u, 1u | 4u, 2u | 8u, 16u, 16u | 2u, 32u | 1u}) {
        for (glm::vec2 uv :
             {glm::vec2(0.1f, 0.2f), glm::vec2(0.5f, 0.5f), glm::vec2(-0.3f, 1.4f), glm::vec2(2.7f, -1.1f)}) {
            cases.push_back(makeCase(VKRT_CASE_TEXTURE, flags, {uv.x, uv.y, uv.x * uv.x * 0.3f, 0},
                                     {uv.x * 10 - 7, 4, float(flags & 3u), 0}));
        }
    }
    for (uint32_t binding : {0u, 1u}) {
        for (glm::vec2 uv : {glm::vec2(0.1f, 0.2f), glm::vec2(0.7f, 0.45f), glm::vec2(-0.3f, 1.4f)}) {
            cases.push_back(makeCase(VKRT_CASE_BINDING, binding, {uv.x, uv.y, 0, 0}, {0.5f, -2.0f, 0.25f, 0},
                                     {1.5f, 0.75f, -3.0f, 0}));
        }
    }
    for (uint32_t projection : {0u, 1u}) {
        for (float lens : {0.0f, 0.2f}) {
            for (glm::vec4 film : {glm::vec4(0.5f, 0.5f, 0.5f, 0.5f), glm::vec4(63.5f, 20, 0.1f, 0.9f),
                                   glm::vec4(31, 47.9f, 0.99f, 0.01f)}) {
                cases.push_back(makeCase(VKRT_CASE_CAMERA, projection, {1, 2, 10, 0.4f}, {0, 0, -1, lens},
                                         {1, 0, 0, 8.0f}, {0, 1, 0, 3.0f}, film));
            }
        }
    }
    // Lenses focused beyond 1.8e19, where the aim's squared length overflowed single precision, up to float's
    // largest value; and one focused nearer than its radius.
    for (float focus : {1e30f, 3.4e38f, 0.05f}) {
        cases.push_back(makeCase(VKRT_CASE_CAMERA, 0, {1, 2, 10, 0.4f}, {0, 0, -1, 0.2f}, {1, 0, 0, focus},
                                 {0, 1, 0, 3.0f}, {63.5f, 20, 0.1f, 0.9f}));
    }
    // A lens far wider than the scene's radius (100 in shading_cases.h), whose rays start nearer, focused
    // near and far.
    for (float focus : {8.0f, 1e30f}) {
        cases.push_back(makeCase(VKRT_CASE_CAMERA, 0, {1, 2, 10, 0.4f}, {0, 0, -1, 1e5f}, {1, 0, 0, focus},
                                 {0, 1, 0, 3.0f}, {63.5f, 20, 0.1f, 0.9f}));
    }
    for (uint32_t filter : {0u, 1u, 2u}) {
        for (glm::vec2 u :
             {glm::vec2(0, 0), glm::vec2(0.25f, 0.75f), glm::vec2(0.5f, 0.5f), glm::vec2(0.999f, 0.01f)}) {
            cases.push_back(makeCase(VKRT_CASE_FILTER, filter, {u.x, u.y, u.x, 0}));
        }
    }
    // Environment samples across the marginal and conditional tables, and directions away from texel edges.
    for (float u1 : {0.03f, 0.3f, 0.62f, 0.97f}) {
        for (float u2 : {0.01f, 0.45f, 0.88f}) {
            cases.push_back(makeCase(VKRT_CASE_ENVIRONMENT, 0, {u1, u2, 0.37f, 0.81f},
                                     direction(0.4 + 2.1 * u1, 6.0 * u2)));
        }
    }
    // Normals in the plane z = 0 with either sign of zero (a face of the Cornell box's blocks has -0): the basis
    // must not depend on it, which a device that ignores the sign of zero (Vulkan allows it) would show.
    for (glm::vec4 n : {glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, -1, 0), glm::vec4(1, 2, 3, 0),
                        glm::vec4(0.3f, -0.2f, -0.9f, 0), glm::vec4(1, 0, 1e-4f, 0), glm::vec4(0, 1, -0.0f, 0),
                        glm::vec4(0.6f, -0.8f, -0.0f, 0), glm::vec4(0.6f, -0.8f, 0, 0)}) {
        cases.push_back(makeCase(VKRT_CASE_BASIS, 0, n));
        cases.push_back(makeCase(VKRT_CASE_ROTATE, 0, n, {0, 1, 0.2f, 0}, {0.5f, -0.5f, 1, 0}));
        cases.push_back(makeCase(VKRT_CASE_ROTATE, 0, n, -n, {0.5f, -0.5f, 1, 0}));
    }
    return cases;
}

// The test texture's texels: sRGB bytes that vary by position; then the test environment map, whose texel
// (x, y) has radiance (x + 1, y + 1, 1), with its tables, as float bits.
std::vector<uint32_t> testTexels() {
    std::vector<uint32_t> texels;
    for (uint32_t i = 0; i < VKRT_CASE_TEXTURE_WIDTH * VKRT_CASE_TEXTURE_HEIGHT; ++i) {
        texels.push_back((i * 37u % 256u) | ((255u - i * 20u) << 8) | ((i * 91u % 256u) << 16) |
                         (200u << 24));
    }
    texels.resize(VKRT_CASE_ENVIRONMENT_FIRST, 0u);
    const int width = VKRT_CASE_ENVIRONMENT_WIDTH, height = VKRT_CASE_ENVIRONMENT_HEIGHT;
    std::vector<glm::vec3> radiance;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) radiance.push_back(glm::vec3(x + 1, y + 1, 1.0f));
    }
    const EnvironmentMap map = makeEnvironmentMap("test", width, height, radiance, 30.0, 1.0);
    const EnvironmentDistribution tables = EnvironmentDistribution::build(map);
    auto word = [&](double value) { texels.push_back(std::bit_cast<uint32_t>(static_cast<float>(value))); };
    for (size_t i = 0; i < map.radiance.size(); ++i) {
        for (int c = 0; c < 3; ++c) word(map.radiance[i][c]);
        word(tables.columnCdf[i]);
    }
    for (double cdf : tables.rowCdf) word(cdf);
    return texels;
}

// The tolerance of each of a case's eight results (r0.xyzw, r1.xyzw).
std::array<Tolerance, 8> tolerances(const FunctionCase& fc) {
    const Tolerance standard{2e-6, 2e-5};
    std::array<Tolerance, 8> t;
    t.fill(standard);
    switch (fc.function) {
        case VKRT_CASE_GGX: {
            // D divides by cos^2 (alpha^2 - 1) + 1, which float resolves only to 2^-24: near the mirror limit
            // its error grows as 1 / that denominator, and so does D's tolerance (the others keep theirs).
            const double cosH = fc.a.x, alpha = fc.a.y;
            const double denominator = std::max(cosH * cosH * (alpha * alpha - 1.0) + 1.0, 1e-300);
            t[0].relative = 1e-5 + 4.0 * 1.2e-7 / std::min(1.0, denominator);
            t[4].relative = t[0].relative;  // the pdf carries D
            break;
        }
        case VKRT_CASE_SPHERE_LIGHT: {
            // Points are as exact as float coordinates of their magnitude allow; normals, texture
            // coordinates and densities are compared as such.
            const double scale =
                std::abs(fc.a.w) + glm::length(glm::dvec3(fc.b)) + glm::length(glm::dvec3(fc.a));
            t[0] = t[1] = t[2] = {4e-6 * scale, 0.0};
            t[3] = t[7] = {0.0, 1e-4};  // densities: relative
            // The point is chosen by angles, through sin and cos, which Vulkan lets a device compute to 2^-11
            // absolute (lavapipe: 5e-5 here), inside the cone the sphere subtends, which float resolves
            // relative to that cone: the normal's error grows with distance / radius.
            const double ratio = glm::length(glm::dvec3(fc.b) - glm::dvec3(fc.a)) / fc.a.w;
            t[4] = t[5] = t[6] = {1e-4 + 1.2e-7 * ratio, 0.0};
            break;
        }
        case VKRT_CASE_SPHERE: {
            // Distances along the ray to a sphere of radius r seen from |from|: float rounds the origin and
            // centre to 6e-8 of their magnitude (the roots are solved in double where the device has it).
            const double scale =
                std::abs(fc.a.w) + glm::length(glm::dvec3(fc.b)) + glm::length(glm::dvec3(fc.a));
            t[0] = t[1] = t[6] = {4e-6 * scale, 1e-5};
            t[2] = {0.0, 0.0};   // hit or miss: exact
            t[3] = {0.0, 1e-4};  // 1 - cos of the subtended cone
            t[4] = t[5] = {2e-5, 0.0};
            break;
        }
        case VKRT_CASE_TRIANGLE_LIGHT: {
            // Points are as exact as the direction to them times the distance from the viewpoint allows; the
            // density per unit area, which scales as 1 / length^2, is compared relative to itself.
            const glm::dvec3 v0(fc.a), v1(fc.b), v2(fc.c), from(fc.c.w, fc.d.z, fc.d.w);
            const double scale = glm::length(v0 - from) + glm::length(v1 - v0) + glm::length(v2 - v0);
            t[0] = t[1] = t[2] = {4e-7 * scale, 2e-5};
            t[3] = {0.0, 2e-5};
            // Seen edge-on, the density per solid angle at a point of the triangle is infinite: float and
            // double round the point's cosine (0) differently.
            if (std::abs(glm::dot(v0 - from, glm::cross(v1 - v0, v2 - v0))) < 1e-9 * scale * scale * scale)
                t[7] = {std::numeric_limits<double>::infinity(), 0.0};
            break;
        }
        case VKRT_CASE_MEDIA:
            t.fill({0.0, 0.0});  // integers: exact
            break;
        case VKRT_CASE_ENVIRONMENT:
            // Directions through sin and cos (2^-11 absolute allowed; lavapipe: 5e-5), densities through
            // sin(theta) likewise, relative to it; which texel is seen: exact.
            t[0] = t[1] = t[2] = {2e-4, 0.0};
            t[3] = t[5] = t[6] = {0.0, 1e-3};
            t[4] = t[7] = {0.0, 0.0};
            break;
        default:
            break;
    }
    return t;
}

TEST_F(ShadingFunctions, GpuMatchesCppFunctionByFunction) {
    const std::vector<FunctionCase> cases = makeCases();
    const std::vector<uint32_t> texels = testTexels();

    // The kernel includes shading_cases.h from tests/glsl; the shaders it includes come from the binary.
    auto read = [](const std::filesystem::path& path) {
        std::ifstream file(path);
        std::stringstream text;
        text << file.rdbuf();
        return text.str();
    };
    std::string source = read(test::sourceDir() / "tests/glsl/shading_functions.comp");
    const std::string include = "#include \"shading_cases.h\"";
    source.replace(source.find(include), include.size(),
                   read(test::sourceDir() / "tests/glsl/shading_cases.h"));
    // Sphere roots in float, as the renderer finds most scenes' (scene_features.cpp), and in double where the
    // device has it, as it finds those of a scene with a large sphere.
    std::vector<bool> doubleRoots{false};
    if (context_->hasShaderFloat64()) doubleRoots.push_back(true);
    for (const bool inDouble : doubleRoots) {
        SCOPED_TRACE(inDouble ? "sphere roots in double" : "sphere roots in float");
        std::vector<std::string> defines;
        if (inDouble) defines.push_back("VKRT_SPHERE_FLOAT64");
        if (context_->keepsIeeeFloats()) defines.push_back("VKRT_IEEE_FLOATS");
        const CompiledShader shader = compileShaderSource("shading_functions.comp", source, defines, "");
        ComputePipeline pipeline(*context_, shader.spirv, 3, sizeof(uint32_t));
        GpuBuffer caseBuffer(*context_, cases);
        GpuBuffer texelBuffer(*context_, texels);
        GpuBuffer results(*context_, cases.size() * 2 * sizeof(glm::vec4));
        pipeline.bind({&caseBuffer, &texelBuffer, &results});
        const uint32_t count = static_cast<uint32_t>(cases.size());
        context_->submitAndWait([&](VkCommandBuffer commands) {
            pipeline.dispatch(commands, &count, sizeof(count), (count + 63) / 64, 1);
            makeShaderWritesVisibleToHost(commands);
        });
        std::vector<glm::vec4> gpu(cases.size() * 2);
        results.download(gpu.data(), gpu.size() * sizeof(glm::vec4));
        EXPECT_EQ(context_->validationMessages(), 0u);

        const TexelDevice device{&texels};
        std::vector<int> checked(VKRT_CASE_COUNT, 0);
        std::vector<double> worst(VKRT_CASE_COUNT, 0.0);  // the largest error as a fraction of its tolerance
        for (size_t i = 0; i < cases.size(); ++i) {
            glm::dvec4 cpu[2];
            shading::evaluateCase(device, cases[i], cpu[0], cpu[1]);
            const std::array<Tolerance, 8> t = tolerances(cases[i]);
            const uint32_t function = cases[i].function;
            ++checked[function];
            for (int row = 0; row < 2; ++row) {
                for (int k = 0; k < 4; ++k) {
                    const double expected = cpu[row][k], actual = gpu[2 * i + row][k];
                    if (!std::isfinite(expected) || !std::isfinite(actual)) {
                        EXPECT_TRUE(expected == actual || (std::isnan(expected) && std::isnan(actual)))
                            << kFunctionNames[function] << ", case " << i << ", result " << row * 4 + k
                            << ": GPU " << actual << ", C++ " << expected;
                        continue;
                    }
                    const Tolerance& tolerance = t[row * 4 + k];
                    const double allowed = tolerance.absolute + tolerance.relative * std::abs(expected);
                    const double error = std::abs(actual - expected);
                    worst[function] = std::max(worst[function], allowed > 0.0 ? error / allowed
                                                                : error > 0.0 ? 1e9
                                                                              : 0.0);
                    EXPECT_LE(error, allowed) << kFunctionNames[function] << ", case " << i << ", result "
                                              << row * 4 + k << ": GPU " << actual << ", C++ " << expected;
                }
            }
        }
        for (uint32_t f = 0; f < VKRT_CASE_COUNT; ++f) {
            EXPECT_GT(checked[f], 0) << kFunctionNames[f] << " has no cases";
            std::printf("%-40s %3d cases, largest error %.3f of its tolerance\n", kFunctionNames[f],
                        checked[f], worst[f]);
        }
    }
}

}  // namespace
}  // namespace vkrt
