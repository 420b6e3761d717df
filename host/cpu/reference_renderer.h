// The CPU reference renderer: plain, recursive, distributed Whitted ray tracing in double precision, of
// triangles and analytic spheres. It is the oracle the GPU tracer is tested against, so it favours obvious
// correctness over speed (rows are still shared among all cores).
#pragma once

#include <cstdint>

#include "bvh/bvh_traversal.h"
#include "bvh/flat_bvh.h"
#include "common/render_settings.h"
#include "cpu/area_lights.h"
#include "cpu/closest_hit.h"
#include "cpu/medium_stack.h"
#include "cpu/whitted_model.h"
#include "scene/scene.h"

namespace vkrt {

using Ray = RayT<double>;

class ReferenceRenderer {
  public:
    ReferenceRenderer(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                      const RenderSettings& settings);

    // Renders every sample. With a checkpoint callback, it is also called with the image so far at every
    // power-of-two sample count, at the end, and after any pass that crosses checkpointEveryMs (> 0).
    RenderResult render(const ProgressCallback& progress = {}, const CheckpointCallback& checkpoint = {},
                        double checkpointEveryMs = 0.0) const;

    // The pieces, public for tests.
    // Film coordinates in pixels, (0, 0) top-left; (lensU, lensV) in [0, 1)^2 picks the lens point.
    Ray cameraRay(double filmX, double filmY, double lensU = 0.5, double lensV = 0.5) const;
    // Fraction of light that passes from the ray's origin to distance tMax: 0 behind an opaque surface,
    // the product of the transmission tints of transmissive ones.
    glm::dvec3 transmittance(const Ray& ray, double tMax, uint32_t excludeA, uint32_t excludeB,
                             double time = 0.0) const;
    // Where in the shutter interval (0: open, 1: close) a sample sees the scene; every ray of the sample's
    // tree shares it.
    double shutterTime(uint32_t pixel, uint32_t sample) const;
    // Radiance arriving along `ray`; `node` numbers the ray-tree node for the random dimensions.
    // `arrivalPdf` is the density with which a glossy lobe chose the ray (0: camera, mirror or refraction).
    glm::dvec3 radiance(const Ray& ray, uint32_t pixel, uint32_t sample, uint32_t node, int depth,
                        const glm::dvec3& throughput, const MediumStack& media, uint32_t exclude,
                        RayCounters& counters, double arrivalPdf = 0.0) const;
    // The sum of the finite samples [firstSample, endSample) of a pixel (rgb) and how many there were (w).
    glm::dvec4 renderPixel(int x, int y, uint32_t firstSample, uint32_t endSample,
                           RayCounters& counters) const;

  private:
    glm::dvec3 directLight(const glm::dvec3& point, double errorScale, const glm::dvec3& normal,
                           const glm::dvec3& geometricNormal, const glm::dvec3& toViewer,
                           const SurfaceResponse& surface, uint32_t self, uint32_t exclude, bool lobeSampled,
                           uint32_t pixel, uint32_t sample, uint32_t node, RayCounters& counters) const;
    glm::dvec2 uvAt(const SurfaceHit& hit) const;
    // A colour factor times its texture (index -1: none) at the hit's texture coordinates.
    glm::dvec3 textured(const glm::vec3& factor, int texture, const SurfaceHit& hit) const;
    glm::dvec3 albedoAt(const Material& material, const SurfaceHit& hit) const;
    glm::dvec3 emissionAt(const Material& material, const SurfaceHit& hit) const;

    const Scene& scene_;
    const FlatBvh& bvh_;
    Camera camera_;
    RenderSettings settings_;
    AreaLights areaLights_;
    double aspect_;
};

}  // namespace vkrt
