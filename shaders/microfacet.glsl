// GGX microfacets in single precision: host/cpu/microfacet.h explains each function and cites its source.
#ifndef VKRT_MICROFACET_GLSL
#define VKRT_MICROFACET_GLSL

float ggxD(float cosH, float alpha) {
    if (cosH <= 0.0) return 0.0;
    const float a2 = alpha * alpha;
    const float d = cosH * cosH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

float ggxLambda(float cosTheta, float alpha) {
    const float c2 = cosTheta * cosTheta;
    if (c2 >= 1.0) return 0.0;
    const float tan2 = (1.0 - c2) / c2;
    return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

float ggxG1(float cosTheta, float alpha) { return 1.0 / (1.0 + ggxLambda(cosTheta, alpha)); }

float ggxG2(float cosOut, float cosIn, float alpha) {
    return 1.0 / (1.0 + ggxLambda(cosOut, alpha) + ggxLambda(cosIn, alpha));
}

vec3 sampleGgxVisibleNormal(vec3 toViewer, float alpha, float u1, float u2) {
    const vec3 vh = normalize(vec3(alpha * toViewer.x, alpha * toViewer.y, toViewer.z));
    const float lengthSquared = vh.x * vh.x + vh.y * vh.y;
    const vec3 t1 = lengthSquared > 0.0 ? vec3(-vh.y, vh.x, 0.0) / sqrt(lengthSquared) : vec3(1.0, 0.0, 0.0);
    const vec3 t2 = cross(vh, t1);
    const float r = sqrt(u1), phi = 2.0 * PI * u2;
    const float p1 = r * cos(phi);
    const float s = 0.5 * (1.0 + vh.z);
    const float p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * r * sin(phi);
    const vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(0.0, nh.z)));
}

float ggxReflectionPdf(float cosOut, float cosH, float alpha) {
    if (cosOut <= 0.0) return 0.0;
    return ggxG1(cosOut, alpha) * ggxD(cosH, alpha) / (4.0 * cosOut);
}

float powerHeuristic(float count, float pdf, float other) {
    const float a = count * pdf;
    const float sum = a * a + other * other;
    return sum > 0.0 ? a * a / sum : 0.0;
}

// Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017.
void orthonormalBasis(vec3 n, out vec3 b1, out vec3 b2) {
    const float sign = n.z >= 0.0 ? 1.0 : -1.0;
    const float a = -1.0 / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = vec3(b, sign + n.y * n.y * a, -n.y);
}

#endif
