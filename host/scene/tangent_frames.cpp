#include "scene/tangent_frames.h"

#include <algorithm>
#include <cmath>

namespace vkrt {
namespace {

struct TriangleDerivatives {
    glm::dvec3 dpdu{0.0}, dpdv{0.0};
    bool valid = false;
    // The image is mirrored on the triangle: its (u, v) turn counter-clockwise, a positive area in the uv
    // plane (glTF's v grows down the image, so an unmirrored triangle's turn clockwise).
    bool mirrored = false;
};

// dP/du and dP/dv of a triangle from its edges and the matching texture coordinate differences.
TriangleDerivatives derivatives(const std::array<glm::dvec3, 3>& p, const std::array<glm::dvec2, 3>& uv) {
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const double determinant = d1.x * d2.y - d2.x * d1.y;
    TriangleDerivatives result;
    if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant)) return result;
    result.dpdu = (e1 * d2.y - e2 * d1.y) / determinant;
    result.dpdv = (e2 * d1.x - e1 * d2.x) / determinant;
    result.mirrored = determinant > 0.0;
    result.valid = std::isfinite(result.dpdu.x + result.dpdu.y + result.dpdu.z + result.dpdv.x + result.dpdv.y +
                                 result.dpdv.z);
    return result;
}

// The tangent frame at a point with unit normal n from accumulated dP/du and dP/dv. A normal texture's +Y is up
// in the image, and glTF's v grows downwards (its origin is the image's top-left corner), so the bitangent
// points along -dP/dv: w is the sign that makes w * cross(n, tangent) agree with it.
glm::vec4 orthogonalFrame(const glm::dvec3& n, const glm::dvec3& dpdu, const glm::dvec3& dpdv) {
    const glm::dvec3 t = dpdu - n * glm::dot(n, dpdu);
    const double length = glm::length(t);
    if (!(length > 1e-20 * glm::length(dpdu)) || !std::isfinite(length)) return glm::vec4(0.0f);
    const glm::dvec3 tangent = t / length;
    const double w = glm::dot(glm::cross(n, tangent), -dpdv) < 0.0 ? -1.0 : 1.0;
    return glm::vec4(glm::dvec4(tangent, w));
}

glm::dvec3 vec3At(const std::vector<float>& v, uint32_t i) {
    return glm::dvec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
}

}  // namespace

VertexTangents vertexTangents(const std::vector<float>& positions, const std::vector<float>& normals,
                              const std::vector<float>& uvs,
                              const std::vector<std::array<uint32_t, 3>>& faces) {
    const size_t vertexCount = positions.size() / 3;
    // The sums over each vertex's faces, then over its mirrored ones.
    std::vector<glm::dvec3> dpdu(2 * vertexCount, glm::dvec3(0.0)), dpdv(2 * vertexCount, glm::dvec3(0.0));
    VertexTangents result;
    result.mirroredFaces.assign(faces.size(), false);
    for (size_t f = 0; f < faces.size(); ++f) {
        const std::array<uint32_t, 3>& face = faces[f];
        std::array<glm::dvec3, 3> p;
        std::array<glm::dvec2, 3> uv;
        for (int k = 0; k < 3; ++k) {
            p[k] = vec3At(positions, face[k]);
            uv[k] = glm::dvec2(uvs[2 * face[k]], uvs[2 * face[k] + 1]);
        }
        const TriangleDerivatives d = derivatives(p, uv);
        if (!d.valid) continue;
        result.mirroredFaces[f] = d.mirrored;
        const size_t sums = d.mirrored ? vertexCount : 0;
        // Each corner gets the triangle's derivatives weighted by its angle, so a vertex's frame does not
        // depend on how finely the faces around it are split.
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
            const double la = glm::length(a), lb = glm::length(b);
            if (!(la > 0.0 && lb > 0.0)) continue;
            const double angle = std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
            dpdu[sums + face[k]] += angle * d.dpdu;
            dpdv[sums + face[k]] += angle * d.dpdv;
        }
    }
    result.frames.assign(4 * vertexCount, 0.0f);
    result.mirroredFrames.assign(4 * vertexCount, 0.0f);
    for (size_t v = 0; v < vertexCount; ++v) {
        const glm::dvec3 n = vec3At(normals, static_cast<uint32_t>(v));
        const double length = glm::length(n);
        if (!(length > 0.0)) continue;
        glm::vec4 frame = orthogonalFrame(n / length, dpdu[v], dpdv[v]);
        glm::vec4 mirrored = orthogonalFrame(n / length, dpdu[vertexCount + v], dpdv[vertexCount + v]);
        // A face with no direction of its own (its texture coordinates collapsed) takes whichever there is.
        if (frame == glm::vec4(0.0f)) frame = mirrored;
        if (mirrored == glm::vec4(0.0f)) mirrored = frame;
        for (int c = 0; c < 4; ++c) {
            result.frames[4 * v + c] = frame[c];
            result.mirroredFrames[4 * v + c] = mirrored[c];
        }
    }
    return result;
}

glm::vec4 faceTangent(const std::array<glm::dvec3, 3>& corners, const std::array<glm::dvec2, 3>& uvs,
                      const glm::dvec3& normal) {
    const TriangleDerivatives d = derivatives(corners, uvs);
    return d.valid ? orthogonalFrame(normal, d.dpdu, d.dpdv) : glm::vec4(0.0f);
}

}  // namespace vkrt
