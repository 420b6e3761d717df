// Watertight ray-triangle intersection: Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection",
// JCGT 2(1), 2013. The ray is sheared so it points along +z; the 2D edge functions then decide
// containment consistently for triangles sharing an edge, so no ray slips between them.
#ifndef VKRT_INTERSECT_GLSL
#define VKRT_INTERSECT_GLSL

struct ShearedRay {
    vec3 origin;
    vec3 direction;
    // The box test's (traverse.glsl's intersectBox): 1 / direction, and the origins its lower and upper faces
    // are measured from. Along an axis the ray does not move in (|direction| below 1e-36: less than 1e-23
    // over the GPU's reach of 1e12, gpu_scene.cpp), the slab holds the ray when the origin lies between the
    // faces, both included: there the inverse is a finite 1e38 (never NaN; products overflow to +-infinity)
    // and the two origins lie n beyond the ray's on either side (n at least twice the origin's ulp and 1e-22),
    // so an origin between or on the faces gives the slab distances below -1e16 and above 1e16, farther than
    // anything within reach. With one origin and 1e30, an origin on the upper face gave 0 there, and the box
    // was missed.
    vec3 inverseDirection;
    vec3 lowerFaceOrigin;
    vec3 upperFaceOrigin;
    int kx, ky, kz;         // the permuted axes, kz the dominant direction
    vec3 shear;             // Sx, Sy, Sz
};

ShearedRay shearRay(Ray ray) {
    ShearedRay r;
    r.origin = ray.origin;
    r.direction = ray.direction;
    const bvec3 still = lessThan(abs(ray.direction), vec3(1e-36));
    r.inverseDirection = mix(1.0 / ray.direction, vec3(1e38), still);
    const vec3 nudge = mix(vec3(0.0), max(abs(ray.origin) * (1.0 / 4194304.0), vec3(1e-22)), still);  // 2^-22
    r.lowerFaceOrigin = ray.origin + nudge;
    r.upperFaceOrigin = ray.origin - nudge;
    // The dominant axis becomes z; swapping x and y keeps the winding when it points backwards.
    vec3 a = abs(ray.direction);
    r.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (ray.direction[r.kz] < 0.0) {
        int swap = r.kx;
        r.kx = r.ky;
        r.ky = swap;
    }
    r.shear = vec3(ray.direction[r.kx] / ray.direction[r.kz], ray.direction[r.ky] / ray.direction[r.kz],
                   1.0 / ray.direction[r.kz]);
    return r;
}

// On a hit in (tMin, tMax): the distance and the barycentric weights of v1 and v2.
bool intersectTriangle(ShearedRay r, GpuPrimitive triangle, float tMin, float tMax, out float t, out float u,
                       out float v) {
    const vec3 a = triangle.v0 - r.origin;
    const vec3 b = triangle.v1 - r.origin;
    const vec3 c = triangle.v2 - r.origin;
    const float ax = a[r.kx] - r.shear.x * a[r.kz];
    const float ay = a[r.ky] - r.shear.y * a[r.kz];
    const float bx = b[r.kx] - r.shear.x * b[r.kz];
    const float by = b[r.ky] - r.shear.y * b[r.kz];
    const float cx = c[r.kx] - r.shear.x * c[r.kz];
    const float cy = c[r.ky] - r.shear.y * c[r.kz];
    // Scaled barycentrics: the edge functions of the projected triangle.
    const float e0 = cx * by - cy * bx;
    const float e1 = ax * cy - ay * cx;
    const float e2 = bx * ay - by * ax;
    t = 0.0;
    u = 0.0;
    v = 0.0;
    if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0)) return false;
    const float determinant = e0 + e1 + e2;
    if (determinant == 0.0) return false;
    const float az = r.shear.z * a[r.kz];
    const float bz = r.shear.z * b[r.kz];
    const float cz = r.shear.z * c[r.kz];
    const float scaledT = e0 * az + e1 * bz + e2 * cz;
    const float inverse = 1.0 / determinant;
    t = scaledT * inverse;
    if (!(t > tMin && t < tMax)) return false;
    u = e1 * inverse;
    v = e2 * inverse;
    return true;
}

#endif
