// Camera rays: where a sample lands in its pixel (filter importance sampling), and the ray a perspective
// (pinhole or thin-lens) or orthographic camera sends through that film position.
#ifndef VKRT_CAMERA_H
#define VKRT_CAMERA_H

#include "shading_language.h"

#define VKRT_PROJECTION_PERSPECTIVE 0u
#define VKRT_PROJECTION_ORTHOGRAPHIC 1u

// Pixel filters: every sample has weight 1 and lands where the filter's density puts it, so averaging gives
// the filtered image. Box: the pixel's square; tent: radius 1 pixel; Gaussian: standard deviation 0.5 pixel.
#define VKRT_FILTER_BOX 0u
#define VKRT_FILTER_TENT 1u
#define VKRT_FILTER_GAUSSIAN 2u

VKRT_SHADING_BEGIN

struct CameraFrame {
    uint projection;  // VKRT_PROJECTION_*
    real3 position;
    real3 forward;
    real3 right;
    real3 up;
    real tanHalfFov;     // perspective: tan(yfov / 2)
    real xmag, ymag;     // orthographic: half the view's width and height
    real lensRadius;     // thin lens (perspective only); 0 is a pinhole
    real focusDistance;  // distance of the plane in focus, along `forward`
    real sceneRadius;    // thin lens: a radius about `position` that holds the whole scene
    real width, height;  // of the image, in pixels
};

struct CameraRay {
    real3 origin;
    real3 direction;
};

// A camera ray's cone (Akenine-Moller et al., Ray Tracing Gems ch. 20): its width where it starts and how
// fast it widens (the spread angle), one pixel across: a perspective camera's rays start as points and
// spread by a pixel's angle; an orthographic camera's keep a pixel's width.
VKRT_FN real2 cameraCone(VKRT_IN(CameraFrame) camera) {
    if (camera.projection == VKRT_PROJECTION_ORTHOGRAPHIC) return real2(2.0 * abs(camera.ymag) / camera.height, 0.0);
    return real2(0.0, 2.0 * camera.tanHalfFov / camera.height);
}

// The inverse CDF of the tent filter of radius 1 on [-1, 1].
VKRT_FN real tentInverse(real u) { return u < 0.5 ? sqrt(2.0 * u) - 1.0 : 1.0 - sqrt(2.0 - 2.0 * u); }

// A sample's offset from its pixel's centre, in pixels, from two numbers in [0, 1).
VKRT_FN real2 filterOffset(uint pixelFilter, real u, real v) {
    if (pixelFilter == VKRT_FILTER_TENT) return real2(tentInverse(u), tentInverse(v));
    if (pixelFilter == VKRT_FILTER_GAUSSIAN) {
        // Box-Muller with standard deviation 0.5 pixel.
        const real radius = 0.5 * sqrt(-2.0 * log(1.0 - u));
        return real2(radius * cos(2.0 * VKRT_PI * v), radius * sin(2.0 * VKRT_PI * v));
    }
    return real2(u - 0.5, v - 0.5);
}

// Shirley and Chiu's concentric map from the unit square to the unit disk.
VKRT_FN real2 concentricDisk(real u, real v) {
    const real a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
    if (a == 0.0 && b == 0.0) return real2(0.0);
    if (abs(a) > abs(b)) {
        const real phi = 0.25 * VKRT_PI * (b / a);
        return a * real2(cos(phi), sin(phi));
    }
    const real phi = 0.5 * VKRT_PI - 0.25 * VKRT_PI * (a / b);
    return b * real2(cos(phi), sin(phi));
}

// The ray through film position (filmX, filmY) in pixels, (0, 0) top-left; with a lens, through the lens
// point that (lensU, lensV) in [0, 1)^2 picks (compiled in with VKRT_HAS_DEPTH_OF_FIELD).
VKRT_FN CameraRay cameraRay(VKRT_IN(CameraFrame) camera, real filmX, real filmY, real lensU, real lensV) {
    // Film position in [-1, 1]^2, +y up.
    const real sx = 2.0 * filmX / camera.width - 1.0;
    const real sy = 1.0 - 2.0 * filmY / camera.height;
    CameraRay ray;
    ray.origin = camera.position;
    if (camera.projection == VKRT_PROJECTION_ORTHOGRAPHIC) {
        ray.origin = camera.position + sx * camera.xmag * camera.right + sy * camera.ymag * camera.up;
        ray.direction = camera.forward;
        return ray;
    }
    const real aspect = camera.width / camera.height;
    ray.direction = normalize(camera.forward + sx * camera.tanHalfFov * aspect * camera.right +
                              sy * camera.tanHalfFov * camera.up);
#ifdef VKRT_HAS_DEPTH_OF_FIELD
    if (!(camera.lensRadius > 0.0)) return ray;
    // Thin lens: rays from every point of the lens meet where the pinhole ray crosses the focal plane, at
    // toFocal * F from the pinhole. The aim toFocal * F - lensOffset is divided by the larger of F and the lens
    // radius before it is normalised: its squared length overflowed single precision for F above 1.8e19 (the
    // GPU drew only background), and F = infinity leaves the pinhole direction, a focus at infinity.
    const real3 toFocal = ray.direction / dot(ray.direction, camera.forward);
    const real2 disk = camera.lensRadius * concentricDisk(lensU, lensV);
    const real3 lensOffset = disk.x * camera.right + disk.y * camera.up;
    ray.origin = camera.position + lensOffset;
    ray.direction = camera.focusDistance >= camera.lensRadius
                        ? normalize(toFocal - lensOffset / camera.focusDistance)
                        : normalize(toFocal * (camera.focusDistance / camera.lensRadius) -
                                    lensOffset / camera.lensRadius);
    // A lens far wider than the scene (up to 1e6 times its reach, render_policy.cpp): a ray from its rim, its
    // origin and aim rounded to float there, landed epsilon times the lens radius off, pixels away on the GPU (a
    // plane in focus, which every lens ray meets where the pinhole's does, came out up to 0.56 off at 2.5e5 times
    // its distance). Such a ray starts instead where it comes within the scene's radius of the pinhole, which
    // skips nothing of the scene: at C - R d, C its point nearest the pinhole, taken from the nearer of the lens
    // point and the focal point. The lens point lies `along` from C on the ray. C's rounding, about epsilon
    // times that point's distance, is added to R: a focus 1e5 and a lens 1e11 times the scene's radius started
    // the ray 0.85% of R inside it in float.
    const real along = dot(lensOffset, ray.direction);
    if (along < -camera.sceneRadius) {
        const real3 focal = toFocal * camera.focusDistance;
        const real3 point = camera.focusDistance * length(toFocal) < length(lensOffset) ? focal : lensOffset;
        const real3 nearest = point - dot(point, ray.direction) * ray.direction;
        const real reach = camera.sceneRadius + 1e-6 * length(point);
        if (along < -reach) ray.origin = camera.position + (nearest - reach * ray.direction);
    }
#endif
    return ray;
}

VKRT_SHADING_END

#endif  // VKRT_CAMERA_H
