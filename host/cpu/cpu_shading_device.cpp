#include "cpu/cpu_shading_device.h"

#include <algorithm>
#include <cmath>

#include "bvh/bvh_traversal.h"
#include "cpu/closest_hit.h"
#include "shape_light.h"

namespace vkrt {

namespace {

glm::dvec3 geometricNormalOf(const Triangle& t) {
    return shading::planeNormal(glm::dvec3(t.v0), glm::dvec3(t.v1), glm::dvec3(t.v2));
}

}  // namespace

CpuShadingScene::CpuShadingScene(const Scene& scene, const FlatBvh& bvh)
    : scene(scene), bvh(bvh), textures(packTextures(scene)), lights(buildLightTable(scene)) {
    for (const Material& m : scene.materials)
        materials.push_back(surfaceMaterial(m, scene.textures, bindings));
    // No surface has holes: every one is opaque, as in the GPU's specialised materials (gpu_scene.cpp).
    if (!scene.surfacesHaveHoles()) {
        for (shading::SurfaceMaterial& m : materials) m.alphaMode = VKRT_ALPHA_OPAQUE;
    }
    shapePick.assign(scene.shapes.size(), 0.0);
    for (size_t i = 0; i < lights.shapes.size(); ++i) {
        if (lights.shapes[i] != kNoPrimitive) shapePick[lights.shapes[i]] = lights.pick[i];
    }
    for (const PunctualLight& light : scene.lights) punctualLights.push_back(punctualLightParams(light));
    volumeHoles = scene.volumesHaveHoles();
    smoothNormals = scene.smoothNormals();
    punctualTable = buildPunctualLightTable(scene);
    if (scene.environment.present()) environment = EnvironmentTables(scene.environment);
    // The sheen's albedo table is computed here, once, rather than by the first shading point that needs it.
    if (std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.hasSheen(); }))
        sheenTable = &sheenAlbedoTable();
    // Likewise the albedo tables of the rough GGX lobes.
    if (std::any_of(scene.materials.begin(), scene.materials.end(), hasRoughSpecular))
        ggxAlbedoTable = &vkrt::ggxAlbedoTable();
    if (std::any_of(scene.materials.begin(), scene.materials.end(), refractsRoughly))
        ggxDielectricAlbedoTable = &vkrt::ggxDielectricAlbedoTable();
}

glm::dvec2 CpuShadingDevice::textureCoordinates(uint32_t primitive, glm::dvec2 hitUv, uint32_t set) const {
    if (!data_.scene.isTriangle(primitive))
        return hitUv;  // spheres and solids carry their texture coordinates
    if (set == 1 && !data_.scene.uv1.empty()) {
        const std::array<glm::vec2, 3>& t = data_.scene.uv1[primitive];
        return shading::barycentric(glm::dvec2(t[0]), glm::dvec2(t[1]), glm::dvec2(t[2]), hitUv);
    }
    const TriangleShading& s = data_.scene.shading[primitive];
    return shading::barycentric(glm::dvec2(s.uv[0]), glm::dvec2(s.uv[1]), glm::dvec2(s.uv[2]), hitUv);
}

double CpuShadingDevice::textureDensity(uint32_t primitive, glm::dvec2 hitUv, uint32_t set) const {
    if (data_.scene.isSolid(primitive))
        return 1.0;  // a solid's footprint is in its shape's units (shade_hit.h)
    if (data_.scene.isSphere(primitive)) {
        return shading::sphereTextureDensity(data_.scene.sphereAt(primitive, time_).radius, hitUv.y);
    }
    const Triangle t = data_.scene.triangleAt(primitive, time_);
    return shading::triangleTextureDensity(glm::dvec3(t.v0), glm::dvec3(t.v1), glm::dvec3(t.v2),
                                           textureCoordinates(primitive, glm::dvec2(0.0), set),
                                           textureCoordinates(primitive, glm::dvec2(1.0, 0.0), set),
                                           textureCoordinates(primitive, glm::dvec2(0.0, 1.0), set));
}

glm::dvec4 CpuShadingDevice::vertexColor(uint32_t primitive, glm::dvec2 hitUv) const {
    const Scene& scene = data_.scene;
    if (scene.vertexColors.empty() || !scene.isTriangle(primitive)) return glm::dvec4(1.0);
    const std::array<glm::vec4, 3>& c = scene.vertexColors[primitive];
    return shading::barycentric(glm::dvec4(c[0]), glm::dvec4(c[1]), glm::dvec4(c[2]), hitUv);
}

shading::LightPoint CpuShadingDevice::sampleAreaLight(double pick, double pickFine, double u, double v,
                                                      const glm::dvec3& from) const {
    const LightTable& lights = data_.lights;
    const glm::uvec2 drawn = shading::lightPickSteps(pick, pickFine);
    const size_t i = lights.find(uint64_t(drawn.x) << 24 | drawn.y);
    const uint32_t primitive = lights.primitives[i];
    if (lights.shapes[i] != kNoPrimitive) {
        const Solid& solid = data_.scene.solidOf(primitive);
        const shading::SolidOperands operands{solid.firstShape, solid.shapeCount, solid.tableLow(),
                                              solid.tableHigh()};
        return shading::sampleShapeLight(*this, primitive, operands, lights.shapes[i], lights.pick[i], u, v);
    }
    if (data_.scene.isSphere(primitive)) {
        const Sphere sphere = data_.scene.sphereAt(primitive, time_);
        shading::LightPoint p =
            shading::sampleSphereLight(primitive, glm::dvec3(sphere.center), sphere.radius, lights.pick[i],
                                       from, shading::sphereSeenThrough(material(sphere.material)), u, v);
        p.material = sphere.material;
        return p;
    }
    const Triangle t = data_.scene.triangleAt(primitive, time_);
    const glm::dvec3 v0(t.v0), v1(t.v1), v2(t.v2);
    // The point is uniform over the triangle as it is now (animations may scale it).
    const double pdfArea = lights.pick[i] / shading::triangleArea(v0, v1, v2);
    shading::LightPoint p = shading::sampleTriangleLight(primitive, v0, v1, v2, lights.pick[i], pdfArea, from,
                                                         lights.solidAngleTriangles, u, v);
    p.material = t.material;
    return p;
}

uint32_t CpuShadingDevice::pickPunctualLight(double pick, double pickFine, double& probability) const {
    const glm::uvec2 drawn = shading::lightPickSteps(pick, pickFine);
    const size_t i = data_.punctualTable.find(uint64_t(drawn.x) << 24 | drawn.y);
    probability = data_.punctualTable.pick[i];
    return static_cast<uint32_t>(i);
}

void CpuShadingDevice::shapeMaps(uint32_t shape, shading::AffineRows& toObject,
                                 shading::AffineRows& toWorld) const {
    glm::dmat4 world, object;
    data_.scene.shapeAt(shape, time_, world, object);
    toObject = shading::affineRows(object);
    toWorld = shading::affineRows(world);
}

double CpuShadingDevice::lightSolidAnglePdf(uint32_t primitive, uint32_t shape, const glm::dvec3& from,
                                            const glm::dvec3& point, double cosLight) const {
    const Scene& scene = data_.scene;
    if (shape != kNoPrimitive)
        return shading::shapeLightSolidAnglePdf(*this, shape, data_.shapePick[shape], from, point, cosLight);
    const double pick = shading::lightPickProbability(
        shading::lightPower(glm::dvec3(scene.materials[scene.materialOf(primitive)].emission),
                            primitiveArea(scene, primitive)),
        data_.lights.totalPower, static_cast<uint32_t>(data_.lights.primitives.size()));
    const glm::dvec3 offset = point - from;
    const double distance2 = glm::dot(offset, offset);
    if (scene.isSphere(primitive)) {
        const Sphere sphere = scene.sphereAt(primitive, time_);
        return shading::sphereLightSolidAnglePdf(glm::dvec3(sphere.center), sphere.radius, pick, from,
                                                 shading::sphereSeenThrough(material(sphere.material)),
                                                 distance2, cosLight);
    }
    const Triangle t = scene.triangleAt(primitive, time_);
    const glm::dvec3 v0(t.v0), v1(t.v1), v2(t.v2);
    return shading::triangleLightSolidAnglePdf(v0, v1, v2, pick, pick / shading::triangleArea(v0, v1, v2),
                                               from, data_.lights.solidAngleTriangles, distance2, cosLight);
}

shading::HitPoint CpuShadingDevice::hitPointOf(const RayT<double>& ray, const SurfaceHit& hit) const {
    const Scene& scene = data_.scene;
    shading::HitPoint p;
    p.primitive = hit.primitive;
    p.material = scene.materialOf(hit.primitive);
    p.sphere = scene.isSphere(hit.primitive);
    p.shape = VKRT_NO_PRIMITIVE;
    p.face = 0;
    p.uv = {hit.u, hit.v};
    p.tangent = glm::dvec4(0.0);
    // The point along the ray. Its error scale, which sizes the new rays' offset (cpu_shading_device.h), is
    // the GPU's (trace.comp's hitPointOf): the smaller of the magnitudes of the ray's numbers and of the
    // surface's, from which the GPU computes the point, so that both renderers offset new rays alike.
    p.position = ray.origin + hit.t * ray.direction;
    const double rayScale = shading::maxAbs(ray.origin) + hit.t;
    p.errorScale = rayScale;
    if (scene.isSolid(hit.primitive)) {
        // The crossed shape and face (encodeCrossing); the point projected onto the face.
        p.shape = static_cast<uint32_t>(hit.u);
        const uint32_t code = static_cast<uint32_t>(hit.v);
        p.face = code / 2u;
        const Shape& shape = scene.shapes[p.shape];
        glm::dmat4 toWorld, toObject;
        scene.shapeAt(p.shape, time_, toWorld, toObject);
        const shading::ShapePoint s =
            shading::shapePoint(shape.type, code / 2u, (code & 1u) != 0u, shading::affineRows(toObject),
                                ray.origin, ray.direction, hit.t);
        p.material = shape.material;
        p.position = glm::dvec3(toWorld * glm::dvec4(s.local, 1.0));
        p.errorScale = std::min(rayScale + shading::maxAbs(glm::dvec3(toWorld[3])),
                                shading::shapeScale(shading::affineRows(toWorld)));
        p.geometricNormal = p.normal = s.normal;
        p.uv = s.uv;
        glm::dvec2 row0, row1;
        shading::tangentFrameTurn(*this, p.material, row0, row1);
        p.tangent = shading::shapeTangent(shape.type, code / 2u, s.local, shading::affineRows(toWorld),
                                          s.normal, row0, row1);
        return p;
    }
    if (p.sphere) {
        // Project the point onto the sphere, which removes the error of the distance (RTG ch. 7).
        const Sphere sphere = scene.sphereAt(hit.primitive, time_);
        const glm::dvec3 center(sphere.center);
        p.geometricNormal = p.normal = glm::normalize(p.position - center);
        p.position = center + static_cast<double>(sphere.radius) * p.normal;
        p.errorScale = std::min(rayScale, shading::maxAbs(center) + sphere.radius);
        p.uv = shading::sphereUv(p.normal);
        glm::dvec2 row0, row1;
        shading::tangentFrameTurn(*this, p.material, row0, row1);
        p.tangent = shading::sphereTangent(p.normal, row0, row1);
        return p;
    }
    const TriangleShading& shading = scene.shading[hit.primitive];
    const Triangle& opened = scene.triangles[hit.primitive];  // at the shutter's opening
    const Triangle now = scene.triangleAt(hit.primitive, time_);
    p.geometricNormal = geometricNormalOf(now);
    p.errorScale =
        std::min(rayScale, std::max({shading::maxAbs(glm::dvec3(now.v0)), shading::maxAbs(glm::dvec3(now.v1)),
                                     shading::maxAbs(glm::dvec3(now.v2))}));
    // A moving triangle turns its vertex normals and tangents (given at the shutter's opening) with its face.
    const auto turned = [&](const glm::dvec3& v) {
        return shading::turnWithFace(v, glm::dvec3(opened.v1 - opened.v0), geometricNormalOf(opened),
                                     glm::dvec3(now.v1 - now.v0), p.geometricNormal, 1e-12);
    };
    p.normal = p.geometricNormal;  // a scene without smooth normals: its faces' own, as on the GPU
    if (data_.smoothNormals) {
        p.normal =
            glm::normalize(shading::barycentric(glm::dvec3(shading.normal[0]), glm::dvec3(shading.normal[1]),
                                                glm::dvec3(shading.normal[2]), glm::dvec2(hit.u, hit.v)));
        if (time_ > 0.0) p.normal = turned(p.normal);
    }
    if (!scene.tangents.empty()) {
        const std::array<glm::vec4, 3>& t = scene.tangents[hit.primitive];
        p.tangent = shading::barycentric(glm::dvec4(t[0]), glm::dvec4(t[1]), glm::dvec4(t[2]),
                                         glm::dvec2(hit.u, hit.v));
        if (time_ > 0.0) p.tangent = glm::dvec4(turned(glm::dvec3(p.tangent)), p.tangent.w);
    }
    return p;
}

bool CpuShadingDevice::shadowThroughHoles(const glm::dvec3& origin, const glm::dvec3& direction, double tMax,
                                          uint32_t exclude, uint32_t light, glm::uvec2& media,
                                          glm::dvec4& passage, glm::dvec3& absorbed, double& tMin) const {
    const RayT<double> ray{origin, direction};
    const double originScale = shading::maxAbs(origin);
    shading::WalkPast past = shading::walkPastFrom(tMin);
    SurfaceHit hit;
    double nearest;
    for (uint32_t layer = 0; layer < VKRT_MAX_ALPHA_LAYERS; ++layer) {
        if (!closestHitPast(data_.scene, data_.bvh, ray, past, tMax, exclude, hit, nearest, time_, light)) {
            ++counters_.shadow;
            return false;
        }
        const shading::HitPoint point = hitPointOf(ray, hit);
        shading::crossInOrder(*this, point, direction, std::max(hit.t - tMin, 0.0), media, passage, absorbed);
        tMin = std::max(tMin, hit.t);
        past = shading::walkPast(past, hit.t, hit.primitive, hit.groupEnd, nearest, originScale);
        if (!(shading::maxComponent(glm::dvec3(passage)) > 0.0)) {
            ++counters_.shadow;
            passage = glm::dvec4(0.0);
            return false;
        }
    }
    tMin = past.end;
    return true;  // counted by the walk that takes the rest
}

glm::dvec4 CpuShadingDevice::shadowTransmittance(const glm::dvec3& origin, const glm::dvec3& direction,
                                                 double tMin, double tMax, uint32_t excludeA,
                                                 uint32_t excludeB) const {
    ++counters_.shadow;
    const Scene& scene = data_.scene;
    const RayT<double> ray{origin, direction};
    glm::dvec4 result(1.0);
    // Each crossing of a transmissive surface multiplies by its tint (a sphere can be crossed twice, a solid
    // more often).
    auto cross = [&](uint32_t primitive, uint32_t material, glm::dvec2 hitUv) {
        const shading::SurfaceMaterial& crossed = data_.materials[material];
        result *= shading::shadowPassageAt(*this, crossed, primitive, hitUv,
                                           data_.volumesBlockShadows && crossed.volume);
    };
    traverseBvh(data_.bvh, ray, tMin, tMax, [&](uint32_t primitive, double& rayMax) {
        if (scene.isSolid(primitive)) {  // never skipped (shade_hit.h's ShadingFrame)
            SolidIntervals intervals =
                solidIntervals(scene, scene.solidOf(primitive), origin, direction, time_);
            shading::CsgCrossing crossing;
            for (double after = tMin; solidCrossing(intervals, after, rayMax, crossing);
                 after = crossing.groupEnd) {
                const uint32_t shape = scene.solidOf(primitive).firstShape + crossing.shape;
                glm::dmat4 toWorld, toObject;
                scene.shapeAt(shape, time_, toWorld, toObject);
                const shading::ShapePoint p =
                    shading::shapePoint(scene.shapes[shape].type, crossing.face, crossing.flip,
                                        shading::affineRows(toObject), origin, direction, crossing.t);
                cross(primitive, scene.shapes[shape].material, p.uv);
                if (shading::maxComponent(glm::dvec3(result)) <= 0.0) return true;
            }
            return false;
        }
        if (primitive == excludeA || primitive == excludeB) return false;
        if (scene.isSphere(primitive)) {
            const Sphere sphere = scene.sphereAt(primitive, time_);
            const glm::dvec3 center(sphere.center);
            double roots[2];
            if (!shading::sphereRoots(center, sphere.radius, origin, direction, roots[0], roots[1]))
                return false;
            for (double t : roots) {
                if (t > tMin && t < rayMax)
                    cross(primitive, sphere.material,
                          shading::sphereUv(glm::normalize(origin + t * direction - center)));
            }
        } else {
            TriangleHit hit;
            const Triangle triangle = scene.triangleAt(primitive, time_);
            if (!intersectTriangle(triangle, origin, direction, tMin, rayMax, hit)) return false;
            cross(primitive, triangle.material, {hit.u, hit.v});
        }
        return shading::maxComponent(glm::dvec3(result)) <= 0.0;  // fully blocked: stop looking
    });
    return result;
}

}  // namespace vkrt
