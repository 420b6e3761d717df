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

vec3 directLight(SurfacePoint surfacePoint, vec3 normal, vec3 geometricNormal, vec3 toViewer, SurfaceResponse surface,
                 uint triangle, uint pixel, uint sampleIndex, uint node, inout uint shadowRays, inout bool complete) {
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
        const vec3 visible = shadowTransmittance(Ray(origin, arrival.toLight), arrival.distance, triangle, VKRT_NO_TRIANGLE,
                                                 complete);
        sum += whittedBrdf(surface, normal, toViewer, arrival.toLight) * arrival.irradiance * cosine * visible;
    }
#endif
#ifdef VKRT_HAS_AREA_LIGHTS
    // lightSamples samples, each of one emissive triangle chosen by power, averaged.
    const uint lightSamples = uint(params.background.w);
    if (params.counts.y > 0u) {
        const uint seed = params.imageDepthSeed.w;
        vec3 areaSum = vec3(0.0);
        for (uint k = 0u; k < lightSamples; ++k) {
            const float pick = vkrtRandom(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_PICK)));
            const float su = vkrtRandom(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_U)));
            const float sv = vkrtRandom(seed, pixel, sampleIndex, vkrtNodeDimension(node, VKRT_DIM_LIGHT(k, VKRT_DIM_LIGHT_V)));
            // The first light whose cumulative power exceeds `pick` (binary search).
            uint lo = 0u, hi = params.counts.y - 1u;
            while (lo < hi) {
                const uint mid = (lo + hi) / 2u;
                if (params.areaLights.areaLights[mid].cdf > pick) hi = mid;
                else lo = mid + 1u;
            }
            const GpuAreaLight light = params.areaLights.areaLights[lo];
            const GpuTriangle emitterTriangle = VKRT_TRIANGLE(light.triangle);
            // Uniform point on the triangle (square-root mapping).
            const float root = sqrt(su);
            const float b1 = root * (1.0 - sv), b2 = root * sv;
            const vec3 lightPoint = (1.0 - root) * emitterTriangle.v0 + b1 * emitterTriangle.v1 + b2 * emitterTriangle.v2;
            const vec3 lightNormal = normalize(cross(emitterTriangle.v1 - emitterTriangle.v0, emitterTriangle.v2 - emitterTriangle.v0));
            const vec3 offset = lightPoint - point;
            const float distance2 = dot(offset, offset);
            const float distance = sqrt(distance2);
            if (light.triangle == triangle || !(distance > 0.0)) continue;
            const vec3 toLight = offset / distance;
            const GpuMaterial emitter = params.materials.materials[materialOf(light.triangle)];
            float cosLight = -dot(lightNormal, toLight);
            if (emitter.transmission.w != 0.0) cosLight = abs(cosLight);  // double-sided emitter
            const float cosine = dot(normal, toLight);
            if (cosLight > 0.0 && cosine > 0.0 && dot(geometricNormal, toLight) > 0.0) {
                ++shadowRays;
                const vec3 visible = shadowTransmittance(Ray(origin, toLight), distance * (1.0 - 1e-5), triangle,
                                                         light.triangle, complete);
                const vec3 irradiance = emissionAt(emitter, light.triangle, b1, b2) * cosLight / (distance2 * light.pdfArea);
                areaSum += whittedBrdf(surface, normal, toViewer, toLight) * irradiance * cosine * visible;
            }
        }
        sum += areaSum / float(lightSamples);
    }
#endif
    return sum;
}

#endif
