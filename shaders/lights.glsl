// Direct light: punctual lights with hard shadows and one sample of the area lights, as in
// host/cpu/reference_renderer.cpp. Requires `params` in scope.
#ifndef VKRT_LIGHTS_GLSL
#define VKRT_LIGHTS_GLSL

#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
struct LightArrival {
    vec3 toLight;
    float distance;
    vec3 irradiance;  // on a surface facing the light
};

// KHR_lights_punctual: intensity / d^2 with the spec's range window and spot cone falloff; lux for
// directional lights.
LightArrival arriveFrom(GpuPunctualLight light, vec3 point) {
    LightArrival arrival;
    const uint type = uint(light.positionType.w);
    if (type == VKRT_LIGHT_DIRECTIONAL) {
        arrival.toLight = -light.directionRange.xyz;
        arrival.distance = VKRT_INFINITY;
        arrival.irradiance = light.radiantColor.rgb;
        return arrival;
    }
    const vec3 offset = light.positionType.xyz - point;
    const float distance2 = dot(offset, offset);
    arrival.distance = sqrt(distance2);
    arrival.toLight = vec3(0.0);
    arrival.irradiance = vec3(0.0);
    if (!(arrival.distance > 0.0)) return arrival;
    arrival.toLight = offset / arrival.distance;
    float attenuation = 1.0 / distance2;
    const float range = light.directionRange.w;
    if (range > 0.0) {
        const float ratio = arrival.distance / range;
        attenuation *= clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    }
    if (type == VKRT_LIGHT_SPOT) {
        const float cd = dot(light.directionRange.xyz, -arrival.toLight);
        const float falloff = clamp((cd - light.cone.x) * light.cone.y, 0.0, 1.0);
        attenuation *= falloff * falloff;
    }
    arrival.irradiance = light.radiantColor.rgb * attenuation;
    return arrival;
}
#endif

#ifdef VKRT_HAS_AREA_LIGHTS
// A point on an emissive primitive, as host/cpu/area_lights.cpp samples it.
struct LightPoint {
    vec3 position;
    vec3 normal;   // the emitting (front, outward) side
    vec2 uv;       // barycentrics of v1 and v2 (triangles) or texture coordinates (spheres)
    float pdfArea; // per unit area, light choice included
};

#ifdef VKRT_HAS_SPHERES
// Uniform in the cone the sphere subtends from `from` (by area from inside); 1 - cos(theta_max) written
// as sin^2 / (1 + cos) keeps its digits for small, distant spheres.
LightPoint sampleSphereLight(GpuTriangle sphere, GpuAreaLight light, vec3 from, float u, float v) {
    LightPoint p;
    const vec3 center = sphere.v0;
    const float radius = sphere.v1.x;
    const vec3 toCenter = center - from;
    const float distance2 = dot(toCenter, toCenter);
    const float phi = 2.0 * PI * v;
    float oneMinusCosMax = 0.0;
    if (distance2 <= radius * radius) {
        const float z = 1.0 - 2.0 * u, ring = sqrt(max(0.0, 1.0 - z * z));
        p.normal = vec3(ring * cos(phi), ring * sin(phi), z);
        p.pdfArea = light.pick / (4.0 * PI * radius * radius);
    } else {
        const vec3 axis = toCenter / sqrt(distance2);
        const float sin2Max = radius * radius / distance2;
        const float sinMax = sqrt(sin2Max);
        oneMinusCosMax = sin2Max / (1.0 + sqrt(max(0.0, 1.0 - sin2Max)));
        const float oneMinusCos = u * oneMinusCosMax;
        const float cosTheta = 1.0 - oneMinusCos;
        const float sin2Theta = oneMinusCos * (2.0 - oneMinusCos);
        const float cosAlpha = sin2Theta / sinMax + cosTheta * sqrt(max(0.0, 1.0 - sin2Theta / sin2Max));
        const float sinAlpha = sqrt(max(0.0, 1.0 - cosAlpha * cosAlpha));
        vec3 b1, b2;
        orthonormalBasis(axis, b1, b2);
        p.normal = -(sinAlpha * cos(phi) * b1 + sinAlpha * sin(phi) * b2 + cosAlpha * axis);
    }
    p.position = center + radius * p.normal;
    p.uv = sphereUv(p.normal);
    if (oneMinusCosMax > 0.0) {
        const vec3 offset = p.position - from;
        const float d2 = dot(offset, offset);
        const float cosLight = max(0.0, -dot(p.normal, offset) / sqrt(d2));
        p.pdfArea = light.pick * cosLight / (2.0 * PI * oneMinusCosMax * d2);
    }
    return p;
}
#endif

LightPoint sampleAreaLight(GpuAreaLight light, vec3 from, float u, float v) {
    const GpuTriangle emitter = primitiveAt(light.triangle);
#ifdef VKRT_HAS_SPHERES
    if (emitter.kind == VKRT_PRIMITIVE_SPHERE) return sampleSphereLight(emitter, light, from, u, v);
#endif
    // Uniform point on the triangle (square-root mapping).
    LightPoint p;
    const float root = sqrt(u);
    p.uv = vec2(root * (1.0 - v), root * v);
    p.position = (1.0 - root) * emitter.v0 + p.uv.x * emitter.v1 + p.uv.y * emitter.v2;
    p.normal = normalize(cross(emitter.v1 - emitter.v0, emitter.v2 - emitter.v0));
#ifdef VKRT_HAS_MOTION
    p.pdfArea = light.pick / (0.5 * length(cross(emitter.v1 - emitter.v0, emitter.v2 - emitter.v0)));
#else
    p.pdfArea = light.pdfArea;
#endif
    return p;
}
#endif

#ifdef VKRT_HAS_AREA_LIGHTS
float luminance(vec3 e) { return 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z; }

// As AreaLights::solidAnglePdf: the density per solid angle, seen from `from`, with which light sampling
// picks `point` on emissive primitive `primitive`.
float triangleArea(GpuTriangle t) { return 0.5 * length(cross(t.v1 - t.v0, t.v2 - t.v0)); }

float lightSolidAnglePdf(uint primitive, vec3 from, vec3 point, float cosLight) {
    if (!(cosLight > 0.0)) return 0.0;
    const GpuMaterial material = params.materials.materials[materialOf(primitive)];
    // Power is luminance times area (at the shutter's opening): the pick probability is that share of the
    // total; the point is then uniform over the primitive as it is now.
    const float luminanceShare = max(luminance(material.emissionRoughness.rgb), 1e-12) / params.lighting.x;
    const vec3 offset = point - from;
    const float distance2 = dot(offset, offset);
#ifdef VKRT_HAS_SPHERES
    const GpuTriangle opened = VKRT_TRIANGLE(primitive);
    if (opened.kind == VKRT_PRIMITIVE_SPHERE) {
        const float pick = luminanceShare * 4.0 * PI * opened.v1.x * opened.v1.x;
        const GpuTriangle sphere = primitiveAt(primitive);
        const float radius = sphere.v1.x;
        const vec3 toCenter = sphere.v0 - from;
        const float centerDistance2 = dot(toCenter, toCenter);
        if (centerDistance2 > radius * radius) {
            const float sin2Max = radius * radius / centerDistance2;
            const float oneMinusCosMax = sin2Max / (1.0 + sqrt(max(0.0, 1.0 - sin2Max)));
            return pick / (2.0 * PI * oneMinusCosMax);
        }
        return pick / (4.0 * PI * radius * radius) * distance2 / cosLight;
    }
#endif
#ifdef VKRT_HAS_MOTION
    return luminanceShare * triangleArea(VKRT_TRIANGLE(primitive)) / triangleArea(primitiveAt(primitive)) * distance2 /
           cosLight;
#else
    return luminanceShare * distance2 / cosLight;
#endif
}
#endif

vec3 directLight(SurfacePoint surfacePoint, vec3 normal, vec3 geometricNormal, vec3 toViewer, SurfaceResponse surface,
                 uint self, uint exclude, bool lobeSampled, uint pixel, uint sampleIndex, uint node, inout uint shadowRays,
                 inout bool complete) {
    vec3 sum = vec3(0.0);
    const vec3 point = surfacePoint.position;
    const vec3 origin = offsetRayOrigin(surfacePoint, geometricNormal);
#ifdef VKRT_HAS_PUNCTUAL_LIGHTS
    for (uint i = 0u; i < params.counts.x; ++i) {
        const LightArrival arrival = arriveFrom(params.lights.lights[i], point);
        const float cosine = dot(normal, arrival.toLight);
        if (cosine <= 0.0 || dot(geometricNormal, arrival.toLight) <= 0.0 || maxComponent(arrival.irradiance) <= 0.0) {
            continue;
        }
        ++shadowRays;
        const vec3 visible = shadowTransmittance(Ray(origin, arrival.toLight), arrival.distance, exclude, VKRT_NO_TRIANGLE,
                                                 complete);
        const vec3 brdf = surface.diffuse / PI + specularBrdf(surface, normal, toViewer, arrival.toLight);
        sum += brdf * arrival.irradiance * cosine * visible;
    }
#endif
#ifdef VKRT_HAS_AREA_LIGHTS
    // lightSamples samples, each of one emissive primitive chosen by power, averaged.
    const uint lightSamples = uint(params.background.w);
    if (params.counts.y > 0u) {
        const uint seed = params.imageDepthSeed.w;
        vec3 areaSum = vec3(0.0);
        for (uint k = 0u; k < lightSamples; ++k) {
            const float pick = vkrtStratified(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_PICK)), 0u);
            const float su = vkrtStratified(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 0u);
            const float sv = vkrtStratified(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)), 1u);
            // The first light whose cumulative power exceeds `pick` (binary search).
            uint lo = 0u, hi = params.counts.y - 1u;
            while (lo < hi) {
                const uint mid = (lo + hi) / 2u;
                if (params.areaLights.areaLights[mid].cdf > pick) hi = mid;
                else lo = mid + 1u;
            }
            const GpuAreaLight light = params.areaLights.areaLights[lo];
            const LightPoint lightPoint = sampleAreaLight(light, point, su, sv);
            const vec3 offset = lightPoint.position - point;
            const float distance2 = dot(offset, offset);
            const float distance = sqrt(distance2);
            if (light.triangle == self || !(distance > 0.0) || !(lightPoint.pdfArea > 0.0)) continue;
            const vec3 toLight = offset / distance;
            const GpuMaterial emitter = params.materials.materials[materialOf(light.triangle)];
            float cosLight = -dot(lightPoint.normal, toLight);
            if (emitter.transmission.w != 0.0) cosLight = abs(cosLight);  // double-sided emitter
            const float cosine = dot(normal, toLight);
            if (cosLight > 0.0 && cosine > 0.0 && dot(geometricNormal, toLight) > 0.0) {
                ++shadowRays;
                const vec3 visible = shadowTransmittance(Ray(origin, toLight), distance * (1.0 - 1e-5), exclude,
                                                         light.triangle, complete);
                const vec3 irradiance = emissionAt(emitter, light.triangle, lightPoint.uv.x, lightPoint.uv.y) * cosLight /
                                        (distance2 * lightPoint.pdfArea);
                // The specular part is also reached by traced lobe rays: weigh the two by the power heuristic.
                float weight = 1.0;
                if (lobeSampled && params.lighting.y != 0.0) {
                    weight = powerHeuristic(float(lightSamples), lightPoint.pdfArea * distance2 / cosLight,
                                            lobePdf(surface, normal, toViewer, toLight));
                }
                const vec3 brdf = surface.diffuse / PI + weight * specularBrdf(surface, normal, toViewer, toLight);
                areaSum += brdf * irradiance * cosine * visible;
            }
        }
        sum += areaSum / float(lightSamples);
    }
#endif
    return sum;
}

#endif
