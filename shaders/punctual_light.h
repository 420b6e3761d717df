// KHR_lights_punctual: the irradiance that a point, spot or directional light delivers to a point, as the
// spec defines it: intensity / d^2 for point and spot lights (candela), with the spec's smooth range window
// and spot cone falloff; lux for directional lights.
#ifndef VKRT_PUNCTUAL_LIGHT_H
#define VKRT_PUNCTUAL_LIGHT_H

#include "shading_language.h"

#define VKRT_LIGHT_POINT 0u
#define VKRT_LIGHT_SPOT 1u
#define VKRT_LIGHT_DIRECTIONAL 2u

// Up to this many punctual lights, every shading point takes light from each (one shadow ray apiece, Whitted's
// hard shadows). Beyond it each of the `lightSamples` light samples picks one, nine tenths by power and a tenth
// uniformly (area_light.h lightPickProbability), from the table host/scene/light_table.h builds: a scene of
// 10,000 point lights took 10,000 shadow rays at every hit, and ran out of lavapipe's loop budget (its pixels
// left out, or darkened where nothing counted the cut).
#define VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO 64u

VKRT_SHADING_BEGIN

struct PunctualLightParams {
    uint type;             // VKRT_LIGHT_*
    real3 position;
    real3 direction;       // the direction the light shines
    real3 intensity;       // colour * intensity
    real range;            // 0: unlimited
    real cosOuter;         // cos(outer cone angle)
    real coneScale;        // 1 / max(0.001, cos(inner) - cos(outer))
};

struct LightArrival {
    real3 toLight;     // unit vector from the shaded point towards the light
    real distance;     // infinity for directional lights
    real3 irradiance;  // on a surface facing the light (multiply by the cosine)
};

VKRT_FN LightArrival arriveFrom(VKRT_IN(PunctualLightParams) light, real3 point) {
    LightArrival arrival;
    if (light.type == VKRT_LIGHT_DIRECTIONAL) {
        arrival.toLight = -light.direction;
        arrival.distance = VKRT_INFINITY;
        arrival.irradiance = light.intensity;
        return arrival;
    }
    const real3 offset = light.position - point;
    const real distance2 = dot(offset, offset);
    arrival.distance = sqrt(distance2);
    arrival.toLight = real3(0.0);
    arrival.irradiance = real3(0.0);
    if (!(arrival.distance > 0.0)) return arrival;
    arrival.toLight = offset / arrival.distance;
    real attenuation = 1.0 / distance2;
    if (light.range > 0.0) {
        const real ratio = arrival.distance / light.range;
        attenuation *= clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    }
    if (light.type == VKRT_LIGHT_SPOT) {
        const real cd = dot(light.direction, -arrival.toLight);
        const real falloff = clamp((cd - light.cosOuter) * light.coneScale, 0.0, 1.0);
        attenuation *= falloff * falloff;
    }
    arrival.irradiance = light.intensity * attenuation;
    return arrival;
}

VKRT_SHADING_END

#endif  // VKRT_PUNCTUAL_LIGHT_H
