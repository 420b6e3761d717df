#include "cpu/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "common/checkpoint_schedule.h"
#include "common/parallel_for.h"
#include "cpu/optics.h"
#include "cpu/pixel_filter.h"
#include "cpu/punctual_light.h"
#include "cpu/texture_lookup.h"
#include "cpu/triangle_intersection.h"
#include "cpu/whitted_model.h"
#include "random.h"

namespace vkrt {
namespace {

// New rays start a hair off the surface, on the side they leave from. The offset is relative to the
// magnitude of the numbers the position was computed from (|origin| + t), so it is scale-invariant; in double
// precision 1e-9 is far above the rounding of the hit point (about 1e-16 relative) and far below any feature
// float geometry can resolve (6e-8). Excluding the triangle just hit removes the remaining risk of hitting it
// again.
glm::dvec3 offsetOrigin(const glm::dvec3& point, double errorScale, const glm::dvec3& geometricNormal,
                        double side) {
    const double magnitude = std::max({std::abs(point.x), std::abs(point.y), std::abs(point.z), errorScale});
    return point + side * 1e-9 * magnitude * geometricNormal;
}

double maxComponent(const glm::dvec3& v) {
    return std::max({v.x, v.y, v.z});
}

// Shirley and Chiu's concentric map from the unit square to the unit disk.
glm::dvec2 concentricDisk(double u, double v) {
    const double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
    if (a == 0.0 && b == 0.0) return glm::dvec2(0.0);
    if (std::abs(a) > std::abs(b)) {
        const double phi = 0.25 * M_PI * (b / a);
        return a * glm::dvec2(std::cos(phi), std::sin(phi));
    }
    const double phi = 0.5 * M_PI - 0.25 * M_PI * (a / b);
    return b * glm::dvec2(std::cos(phi), std::sin(phi));
}

glm::dvec3 geometricNormalOf(const Triangle& t) {
    return glm::normalize(
        glm::cross(glm::dvec3(t.v1) - glm::dvec3(t.v0), glm::dvec3(t.v2) - glm::dvec3(t.v0)));
}

// Beer-Lambert: transmittance over `distance` inside a volume material.
glm::dvec3 beerLambert(const Material& material, double distance) {
    glm::dvec3 result(1.0);
    if (!std::isfinite(material.attenuationDistance)) return result;
    for (int c = 0; c < 3; ++c) {
        const double color = material.attenuationColor[c];
        if (color >= 1.0) continue;
        if (color <= 0.0 || !std::isfinite(distance)) {
            result[c] = distance > 0.0 ? 0.0 : 1.0;
            continue;
        }
        const double sigma = -std::log(color) / material.attenuationDistance;
        result[c] = std::exp(-sigma * distance);
    }
    return result;
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const Scene& scene, const FlatBvh& bvh, const Camera& camera,
                                     const RenderSettings& settings)
    : scene_(scene),
      bvh_(bvh),
      camera_(camera),
      settings_(settings),
      areaLights_(scene),
      aspect_(static_cast<double>(settings.width) / settings.height) {}

double ReferenceRenderer::shutterTime(uint32_t pixel, uint32_t sample) const {
    return scene_.moving() ? vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_TIME, 0) : 0.0;
}

Ray ReferenceRenderer::cameraRay(double filmX, double filmY, double lensU, double lensV) const {
    // Film position in [-1, 1]^2, +y up.
    const double sx = 2.0 * filmX / settings_.width - 1.0;
    const double sy = 1.0 - 2.0 * filmY / settings_.height;
    if (camera_.projection == Projection::Orthographic) {
        const glm::dvec3 origin =
            camera_.position + sx * camera_.xmag * camera_.right + sy * camera_.ymag * camera_.up;
        return {origin, camera_.forward};
    }
    const double tanHalf = std::tan(0.5 * camera_.yfov);
    const glm::dvec3 direction =
        glm::normalize(camera_.forward + sx * tanHalf * aspect_ * camera_.right + sy * tanHalf * camera_.up);
    if (!(camera_.aperture > 0.0)) return {camera_.position, direction};
    // Thin lens: rays from every point of the lens meet where the pinhole ray crosses the focal plane.
    const glm::dvec3 focus =
        camera_.position + direction * (camera_.focusDistance / glm::dot(direction, camera_.forward));
    const glm::dvec2 disk = camera_.aperture * concentricDisk(lensU, lensV);
    const glm::dvec3 origin = camera_.position + disk.x * camera_.right + disk.y * camera_.up;
    return {origin, glm::normalize(focus - origin)};
}

glm::dvec2 ReferenceRenderer::uvAt(const SurfaceHit& hit) const {
    if (scene_.isSphere(hit.triangle)) return {hit.u, hit.v};  // spheres carry their texture coordinates
    const TriangleShading& s = scene_.shading[hit.triangle];
    return (1.0 - hit.u - hit.v) * glm::dvec2(s.uv[0]) + hit.u * glm::dvec2(s.uv[1]) +
           hit.v * glm::dvec2(s.uv[2]);
}

glm::dvec3 ReferenceRenderer::textured(const glm::vec3& factor, int texture, const SurfaceHit& hit) const {
    glm::dvec3 color(factor);
    if (texture >= 0) color *= glm::dvec3(sampleBaseColor(scene_.textures[texture], uvAt(hit)));
    return color;
}

glm::dvec3 ReferenceRenderer::albedoAt(const Material& material, const SurfaceHit& hit) const {
    return textured(glm::vec3(material.baseColor), material.baseColorTexture, hit);
}

glm::dvec3 ReferenceRenderer::emissionAt(const Material& material, const SurfaceHit& hit) const {
    return textured(material.emission, material.emissiveTexture, hit);
}

glm::dvec3 ReferenceRenderer::transmittance(const Ray& ray, double tMax, uint32_t excludeA, uint32_t excludeB,
                                            double time) const {
    glm::dvec3 result(1.0);
    double limit = tMax;
    // Each crossing of a transmissive surface multiplies by its tint (a sphere can be crossed twice).
    auto cross = [&](uint32_t prim, const SurfaceHit& at) {
        const Material& material = scene_.materials[scene_.materialOf(prim)];
        const double transmission = (1.0 - material.metallic) * material.transmission;
        result *= transmission * albedoAt(material, at);
    };
    traverseBvh(bvh_, ray, 0.0, limit, [&](uint32_t prim, double& rayMax) {
        if (prim == excludeA || prim == excludeB) return false;
        if (scene_.isSphere(prim)) {
            const Sphere sphere = scene_.sphereAt(prim, time);
            double roots[2];
            if (!sphereRoots(glm::dvec3(sphere.center), sphere.radius, ray.origin, ray.direction, roots[0],
                             roots[1])) {
                return false;
            }
            for (double t : roots) {
                if (!(t > 0.0 && t < rayMax)) continue;
                const glm::dvec2 uv =
                    sphereUv(glm::normalize(ray.origin + t * ray.direction - glm::dvec3(sphere.center)));
                cross(prim, {prim, t, uv.x, uv.y});
            }
        } else {
            TriangleHit hit;
            if (!intersectTriangle(scene_.triangleAt(prim, time), ray.origin, ray.direction, 0.0, rayMax,
                                   hit)) {
                return false;
            }
            cross(prim, {prim, hit.t, hit.u, hit.v});
        }
        return maxComponent(result) <= 0.0;  // fully blocked: stop looking
    });
    return result;
}

glm::dvec3 ReferenceRenderer::directLight(const glm::dvec3& point, double errorScale,
                                          const glm::dvec3& normal, const glm::dvec3& geometricNormal,
                                          const glm::dvec3& toViewer, const SurfaceResponse& surface,
                                          uint32_t self, uint32_t exclude, bool lobeSampled, uint32_t pixel,
                                          uint32_t sample, uint32_t node, RayCounters& counters) const {
    const double time = shutterTime(pixel, sample);
    glm::dvec3 sum(0.0);
    const glm::dvec3 origin = offsetOrigin(point, errorScale, geometricNormal, 1.0);
    // Punctual lights: hard shadows.
    for (const PunctualLight& light : scene_.lights) {
        const LightArrival arrival = arriveFrom(light, point);
        const double cosine = glm::dot(normal, arrival.toLight);
        if (cosine <= 0.0 || glm::dot(geometricNormal, arrival.toLight) <= 0.0 ||
            maxComponent(arrival.irradiance) <= 0.0) {
            continue;
        }
        ++counters.shadow;
        const glm::dvec3 visible =
            transmittance({origin, arrival.toLight}, arrival.distance, exclude, kNoTriangle, time);
        const glm::dvec3 brdf =
            surface.diffuse / M_PI + specularBrdf(surface, normal, toViewer, arrival.toLight);
        sum += brdf * arrival.irradiance * cosine * visible;
    }
    // Area lights: lightSamples samples, each of one emissive primitive chosen by power, averaged.
    if (!areaLights_.empty()) {
        const uint32_t seed = settings_.seed;
        const uint32_t count = static_cast<uint32_t>(settings_.lightSamples);
        glm::dvec3 areaSum(0.0);
        for (uint32_t k = 0; k < count; ++k) {
            const AreaLightSample light = areaLights_.sample(
                vkrtStratified(seed, pixel, sample,
                               vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_PICK)), 0),
                vkrtStratified(seed, pixel, sample,
                               vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 0),
                vkrtStratified(seed, pixel, sample,
                               vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 1),
                point, time);
            const glm::dvec3 offset = light.point - point;
            const double distance2 = glm::dot(offset, offset);
            const double distance = std::sqrt(distance2);
            if (light.primitive == self || !(distance > 0.0) || !(light.pdfArea > 0.0)) continue;
            const glm::dvec3 toLight = offset / distance;
            const Material& emitter = scene_.materials[scene_.materialOf(light.primitive)];
            double cosLight = -glm::dot(light.normal, toLight);
            if (emitter.doubleSided) cosLight = std::abs(cosLight);
            const double cosine = glm::dot(normal, toLight);
            if (cosLight > 0.0 && cosine > 0.0 && glm::dot(geometricNormal, toLight) > 0.0) {
                ++counters.shadow;
                const glm::dvec3 visible =
                    transmittance({origin, toLight}, distance * (1.0 - 1e-9), exclude, light.primitive, time);
                // Irradiance estimate: L_e cos(theta_light) / (d^2 pdf_area).
                const glm::dvec3 irradiance = emissionAt(emitter, {light.primitive, 0.0, light.u, light.v}) *
                                              cosLight / (distance2 * light.pdfArea);
                // The specular part is also reached by traced lobe rays: weigh the two by the power
                // heuristic.
                double weight = 1.0;
                if (lobeSampled && settings_.multipleImportanceSampling) {
                    weight = powerHeuristic(count, light.pdfArea * distance2 / cosLight,
                                            lobePdf(surface, normal, toViewer, toLight));
                }
                const glm::dvec3 brdf =
                    surface.diffuse / M_PI + weight * specularBrdf(surface, normal, toViewer, toLight);
                areaSum += brdf * irradiance * cosine * visible;
            }
        }
        sum += areaSum / static_cast<double>(count);
    }
    return sum;
}

glm::dvec3 ReferenceRenderer::radiance(const Ray& ray, uint32_t pixel, uint32_t sample, uint32_t node,
                                       int depth, const glm::dvec3& throughput, const MediumStack& media,
                                       uint32_t exclude, RayCounters& counters, double arrivalPdf) const {
    const double time = shutterTime(pixel, sample);
    SurfaceHit hit;
    const bool found =
        closestHit(scene_, bvh_, ray, std::numeric_limits<double>::infinity(), exclude, hit, time);
    const glm::dvec3 absorbed = media.top() >= 0
                                    ? beerLambert(scene_.materials[media.top()], found ? hit.t : INFINITY)
                                    : glm::dvec3(1.0);
    if (!found) return absorbed * settings_.background;

    const uint32_t primitive = hit.triangle;
    const uint32_t materialIndex = scene_.materialOf(primitive);
    const Material& material = scene_.materials[materialIndex];
    const glm::dvec3 toViewer = -ray.direction;
    glm::dvec3 point = ray.origin + hit.t * ray.direction;
    // The magnitude of the numbers `point` came from; rounding errors are relative to it.
    double errorScale =
        std::max({std::abs(ray.origin.x), std::abs(ray.origin.y), std::abs(ray.origin.z)}) + hit.t;
    glm::dvec3 geometricNormal, normal;  // facing the front (outside) until oriented below
    if (scene_.isSphere(primitive)) {
        // Project the point onto the sphere, which removes the error of the distance (RTG ch. 7).
        const Sphere sphere = scene_.sphereAt(primitive, time);
        const glm::dvec3 center(sphere.center);
        geometricNormal = normal = glm::normalize(point - center);
        point = center + static_cast<double>(sphere.radius) * normal;
        errorScale = std::max({std::abs(center.x), std::abs(center.y), std::abs(center.z)}) + sphere.radius;
        const glm::dvec2 uv = sphereUv(normal);
        hit.u = uv.x;
        hit.v = uv.y;
    } else {
        const TriangleShading& shading = scene_.shading[primitive];
        geometricNormal = geometricNormalOf(scene_.triangleAt(primitive, time));
        normal =
            glm::normalize((1.0 - hit.u - hit.v) * glm::dvec3(shading.normal[0]) +
                           hit.u * glm::dvec3(shading.normal[1]) + hit.v * glm::dvec3(shading.normal[2]));
        // A moving triangle turns its vertex normals (given at the shutter's opening) with its face.
        if (time > 0.0) {
            normal = rotateLike(normal, geometricNormalOf(scene_.triangles[primitive]), geometricNormal);
        }
    }

    // Orient both normals towards the viewer; remember which side was hit.
    const bool frontFace = glm::dot(geometricNormal, toViewer) > 0.0;
    if (!frontFace) {
        geometricNormal = -geometricNormal;
        normal = -normal;
    }
    if (!(glm::dot(normal, toViewer) > 0.0))
        normal = geometricNormal;  // shading normal faces away: use the true one
    // New rays skip the primitive they leave, except rays that go into a sphere (they must find its far
    // side); a ray leaving a sphere's outside cannot meet the sphere again.
    const bool sphere = scene_.isSphere(primitive);
    const uint32_t excludeOnViewerSide = sphere && !frontFace ? kNoTriangle : primitive;
    const uint32_t excludeBeyond = sphere && frontFace ? kNoTriangle : primitive;

    glm::dvec3 result(0.0);
    if (frontFace || material.doubleSided) {
        double weight = 1.0;
        if (arrivalPdf > 0.0 && !areaLights_.empty() && !settings_.multipleImportanceSampling) {
            weight = 0.0;  // light samples alone light the lobe
        } else if (arrivalPdf > 0.0 && !areaLights_.empty()) {
            // A traced lobe ray found a light that light sampling also reaches (multiple importance
            // sampling).
            const double lightPdf = areaLights_.solidAnglePdf(
                primitive, ray.origin, point, std::abs(glm::dot(geometricNormal, ray.direction)), time);
            weight = powerHeuristic(1.0, arrivalPdf, settings_.lightSamples * lightPdf);
        }
        result += weight * emissionAt(material, hit);
    }

    const SurfaceResponse surface = surfaceResponse(material, albedoAt(material, hit));
    // Ambient light reaches the diffuse part, and the specular part where it is not traced.
    result += settings_.ambient * (surface.diffuse + (surface.traced ? glm::dvec3(0.0) : surface.specular));
    const bool lobeSampled = surface.traced && !surface.mirror && depth < settings_.maxDepth;
    result += directLight(point, errorScale, normal, geometricNormal, toViewer, surface, primitive,
                          excludeOnViewerSide, lobeSampled, pixel, sample, node, counters);

    if (depth < settings_.maxDepth && surface.traced) {
        // The weight of this branch of the ray tree so far, absorption on the way here included.
        const glm::dvec3 pathThroughput = throughput * absorbed;
        // Relative index across this interface. A volume is entered through its front face and left through
        // its back face, from the medium the ray is in into the one beyond (nested dielectrics); thin-walled
        // and opaque materials look the same from both sides.
        const bool volume = material.hasVolume() && surface.transmission > 0.0;
        const int self = static_cast<int>(materialIndex);
        const MediumStack beyond = volume ? (frontFace ? media.entered(self) : media.exited(self)) : media;
        const double eta = volume ? mediumIor(scene_, beyond) / mediumIor(scene_, media) : surface.ior;
        // The microfacet normal both branches share: the shading normal for a mirror, else a visible normal.
        const double cosOut = glm::dot(normal, toViewer);
        glm::dvec3 microNormal = normal;
        if (!surface.mirror) {
            glm::dvec3 tangent, bitangent;
            orthonormalBasis(normal, tangent, bitangent);
            const glm::dvec3 local(glm::dot(toViewer, tangent), glm::dot(toViewer, bitangent), cosOut);
            const glm::dvec3 m = sampleGgxVisibleNormal(
                local, surface.alpha,
                vkrtStratified(settings_.seed, pixel, sample, vkrtNodeDimension(node, VKRT_DIM_LOBE_U), 0),
                vkrtStratified(settings_.seed, pixel, sample, vkrtNodeDimension(node, VKRT_DIM_LOBE_U), 1));
            microNormal = glm::normalize(m.x * tangent + m.y * bitangent + m.z * normal);
        }
        const double cosMicro = std::max(0.0, glm::dot(microNormal, toViewer));
        const double dielectric = fresnelDielectric(cosMicro, eta);
        // Reflection: Fresnel, times G2 / G1 for a sampled visible normal (Heitz 2018, eq. 19).
        const glm::dvec3 reflected = reflect(toViewer, microNormal);
        glm::dvec3 reflectWeight = fresnelAt(surface, cosMicro, eta);
        double reflectPdf = 0.0;  // 0: a delta lobe, whose rays see lights at full weight
        if (!surface.mirror) {
            const double cosIn = glm::dot(normal, reflected);
            const bool above = cosIn > 0.0 && glm::dot(geometricNormal, reflected) > 0.0;
            reflectWeight *= above ? ggxG2(cosOut, cosIn, surface.alpha) / ggxG1(cosOut, surface.alpha) : 0.0;
            reflectPdf = ggxReflectionPdf(cosOut, glm::dot(normal, microNormal), surface.alpha);
        }
        // Transmission through the same microfacet; thin-walled surfaces pass rays straight through.
        glm::dvec3 transmitWeight = surface.transmission * (1.0 - dielectric) * surface.albedo;
        glm::dvec3 direction = ray.direction;
        bool passes = maxComponent(transmitWeight) > 0.0;
        if (passes && volume) passes = refract(toViewer, microNormal, eta, direction);
        if (passes && volume && !surface.mirror) {
            const double cosIn = glm::dot(normal, direction);
            passes = cosIn < 0.0 && glm::dot(geometricNormal, direction) < 0.0;
            if (passes) transmitWeight *= ggxG2(cosOut, -cosIn, surface.alpha) / ggxG1(cosOut, surface.alpha);
        }

        if (maxComponent(pathThroughput * reflectWeight) >= settings_.minThroughput) {
            ++counters.secondary;
            const Ray next{offsetOrigin(point, errorScale, geometricNormal, 1.0), reflected};
            result += reflectWeight * radiance(next, pixel, sample, 2 * node + 1, depth + 1,
                                               pathThroughput * reflectWeight, media, excludeOnViewerSide,
                                               counters, reflectPdf);
        }
        if (passes && maxComponent(pathThroughput * transmitWeight) >= settings_.minThroughput) {
            ++counters.secondary;
            const Ray next{offsetOrigin(point, errorScale, geometricNormal, -1.0), direction};
            result +=
                transmitWeight * radiance(next, pixel, sample, 2 * node + 2, depth + 1,
                                          pathThroughput * transmitWeight, beyond, excludeBeyond, counters);
        }
    }
    return absorbed * result;
}

glm::dvec4 ReferenceRenderer::renderPixel(int x, int y, uint32_t firstSample, uint32_t endSample,
                                          RayCounters& counters) const {
    const uint32_t pixel = static_cast<uint32_t>(y) * settings_.width + x;
    glm::dvec3 sum(0.0);
    uint64_t finite = 0;
    for (uint32_t sample = firstSample; sample < endSample; ++sample) {
        // Scrambled (0,2)-sequence positions: stratified at every power-of-two sample count.
        const double jx = vkrtPixelJitterX(settings_.seed, pixel, sample);
        const double jy = vkrtPixelJitterY(settings_.seed, pixel, sample);
        const glm::dvec2 offset = filterOffset(settings_.pixelFilter, jx, jy);
        ++counters.primary;
        const Ray ray = cameraRay(x + 0.5 + offset.x, y + 0.5 + offset.y,
                                  vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_LENS_U, 0),
                                  vkrtStratified(settings_.seed, pixel, sample, VKRT_DIM_LENS_U, 1));
        const glm::dvec3 value =
            radiance(ray, pixel, sample, 0, 0, glm::dvec3(1.0), MediumStack{}, kNoTriangle, counters);
        if (std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z)) {
            sum += value;
            ++finite;
        } else {
            ++counters.nonFiniteSamples;
        }
    }
    return glm::dvec4(sum, static_cast<double>(finite));
}

RenderResult ReferenceRenderer::render(const ProgressCallback& progress, const CheckpointCallback& checkpoint,
                                       double checkpointEveryMs) const {
    RenderResult result;
    result.image = Image(settings_.width, settings_.height);
    const uint32_t spp = static_cast<uint32_t>(settings_.samplesPerPixel);
    const uint64_t pixels = static_cast<uint64_t>(settings_.width) * settings_.height;
    std::vector<glm::dvec4> sums(pixels, glm::dvec4(0.0));
    const unsigned threads = threadCount(settings_.threads);
    CheckpointSchedule schedule(spp, static_cast<bool>(checkpoint), checkpointEveryMs);

    // Passes of samples over all rows, ending where the schedule says. Per pixel the samples are summed in
    // the same order either way, so the image does not depend on the passes.
    uint32_t done = 0;
    while (done < spp) {
        const uint32_t end = schedule.passEnd(done);
        std::atomic<uint64_t> rowsDone{0};
        std::mutex progressLock;
        std::vector<RayCounters> counters(threads);
        parallelFor(static_cast<size_t>(settings_.height), threads, [&](size_t row, unsigned worker) {
            const int y = static_cast<int>(row);
            for (int x = 0; x < settings_.width; ++x) {
                sums[static_cast<size_t>(y) * settings_.width + x] +=
                    renderPixel(x, y, done, end, counters[worker]);
            }
            const uint64_t rows = ++rowsDone;
            if (progress) {
                std::lock_guard<std::mutex> lock(progressLock);
                progress(static_cast<uint64_t>(done) * settings_.height + rows * (end - done),
                         static_cast<uint64_t>(spp) * settings_.height);
            }
        });
        for (const RayCounters& c : counters) {
            result.rays.primary += c.primary;
            result.rays.shadow += c.shadow;
            result.rays.secondary += c.secondary;
            result.rays.nonFiniteSamples += c.nonFiniteSamples;
        }
        done = end;

        const double renderMs = schedule.renderMs();
        if (schedule.due(done, renderMs)) {
            schedule.take(renderMs, [&] {
                checkpoint(done, renderMs, 0.0, averageOf(sums, settings_.width, settings_.height));
            });
        }
    }
    result.image = averageOf(sums, settings_.width, settings_.height);
    return result;
}

}  // namespace vkrt
