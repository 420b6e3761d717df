// The common language of the physics that the GPU tracer and the CPU reference share: headers under shaders/
// that include this one compile as GLSL, in single precision, and as C++, in double precision over GLM. The
// physics is written once; only the integrator loops, the BVH walks and the ray offsets stay per device
// (README.md, "How it is built").
//
// Shared code keeps to the subset both languages read alike:
// - scalars and vectors are `real`, `real2`, `real3`, `real4` (float/vec in GLSL, double/dvec in C++);
//   integers are `uint`, `int`, `uvec2`, `uvec4`;
// - a value that must be evaluated as written, each product rounded before it is added (no fused multiply-add),
//   is declared VKRT_PRECISE (GLSL's `precise`; C++ builds do not contract);
// - functions are declared VKRT_FN; GLSL `out`/`inout` parameters are VKRT_OUT(T)/VKRT_INOUT(T), C++
//   references; structs are passed as VKRT_IN(T), by value in GLSL and by const reference in C++;
// - structs are declared, then filled member by member (no constructors, no aggregate initialisers);
// - a loop of a constant trip count that the GPU should unroll is marked VKRT_UNROLL;
// - no swizzles (GLM has none without GLM_FORCE_SWIZZLE), no buffer access, no globals;
// - what the device owns (buffers, the BVH, counters, the precision of ray offsets) is reached through
//   VKRT_DEVICE(name)(...): a member of the `device` object passed to VKRT_DEVICE_TEMPLATE functions in C++,
//   a free function named device_<name> in GLSL.
#ifndef VKRT_SHADING_LANGUAGE_H
#define VKRT_SHADING_LANGUAGE_H

#define VKRT_PI 3.14159265358979323846
#define VKRT_NO_PRIMITIVE 0xffffffffu

#ifdef __cplusplus
#include <cmath>
#include <bit>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace vkrt::shading {

using real = double;
using real2 = glm::dvec2;
using real3 = glm::dvec3;
using real4 = glm::dvec4;
using uint = uint32_t;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;

using glm::abs;
using glm::acos;
using glm::atan;
using glm::clamp;
using glm::cos;
using glm::cross;
using glm::dot;
using glm::exp;
using glm::floor;
using glm::isinf;
using glm::isnan;
using glm::length;
using glm::log;
using glm::max;
using glm::min;
using glm::mix;
using glm::normalize;
using glm::pow;
using glm::sin;
using glm::sqrt;

inline constexpr real kInfinity = std::numeric_limits<double>::infinity();

// GLSL's findLSB: the index of the lowest set bit, -1 for none.
inline int findLSB(uint bits) { return bits == 0u ? -1 : std::countr_zero(bits); }

}  // namespace vkrt::shading

#define VKRT_FN inline
#define VKRT_PRECISE
#define VKRT_IN(T) const T&
#define VKRT_OUT(T) T&
#define VKRT_INOUT(T) T&
#define VKRT_INFINITY ::vkrt::shading::kInfinity
#define VKRT_DEVICE_TEMPLATE template <typename Device>
#define VKRT_DEVICE_PARAM const Device &device,
#define VKRT_DEVICE_ARG device,
#define VKRT_DEVICE_PARAM_ONLY const Device &device
#define VKRT_DEVICE_ARG_ONLY device
#define VKRT_DEVICE(name) device.name
#define VKRT_SHADING_BEGIN namespace vkrt::shading {
#define VKRT_SHADING_END }
#define VKRT_UNROLL

// The CPU reference compiles every feature; GPU shader variants define only those their scene uses
// (host/gpu/scene_features.cpp), and shared code tests them with #ifdef.
#define VKRT_HAS_SMOOTH_NORMALS
#define VKRT_HAS_TEXTURES
#define VKRT_HAS_TRANSMISSION
#define VKRT_HAS_VOLUMES
#define VKRT_HAS_THIN_TRANSMISSION
#define VKRT_HAS_ABSORPTION
#define VKRT_HAS_PUNCTUAL_LIGHTS
#define VKRT_HAS_PUNCTUAL_LIGHT_TABLE  // used where the scene has more than VKRT_EVERY_PUNCTUAL_LIGHT_UP_TO
#define VKRT_HAS_AREA_LIGHTS
#define VKRT_HAS_SPHERES
#define VKRT_HAS_SHAPES
#define VKRT_HAS_CSG
#define VKRT_HAS_MOTION
#define VKRT_HAS_DEPTH_OF_FIELD
#define VKRT_HAS_VERTEX_COLORS
#define VKRT_HAS_TEXCOORD1
#define VKRT_HAS_NORMAL_MAPS
#define VKRT_HAS_ALPHA
#define VKRT_HAS_VOLUME_HOLES  // and the device says whether the scene has them (hasVolumeHoles)
#define VKRT_HAS_UNLIT
#define VKRT_HAS_MIPMAPS
#define VKRT_HAS_CLEARCOAT
#define VKRT_HAS_ENVIRONMENT
#define VKRT_HAS_SHEEN
#define VKRT_HAS_ROUGH_SPECULAR
#define VKRT_HAS_TRACED_LOBES
#define VKRT_HAS_GLOSSY_LOBES
#define VKRT_HAS_ROUGH_REFRACTION
#define VKRT_HAS_SOLID_ANGLE_TRIANGLES  // and the scene's LightTable says whether it is used

#else  // GLSL

#define real float
#define real2 vec2
#define real3 vec3
#define real4 vec4
#define VKRT_FN
#define VKRT_PRECISE precise
#define VKRT_IN(T) T
#define VKRT_OUT(T) out T
#define VKRT_INOUT(T) inout T
#define VKRT_INFINITY uintBitsToFloat(0x7f800000u)
#define VKRT_DEVICE_TEMPLATE
#define VKRT_DEVICE_PARAM
#define VKRT_DEVICE_ARG
#define VKRT_DEVICE_PARAM_ONLY
#define VKRT_DEVICE_ARG_ONLY
#define VKRT_DEVICE(name) device_##name
#define VKRT_SHADING_BEGIN
#define VKRT_SHADING_END
// A loop of a constant trip count to unroll on the GPU (GLSL's [[unroll]]): spirv-opt unrolls it for
// Whitted's kernel, so lavapipe's NIR passes, paid by every render, get straight code (issue 13: the media
// stack's and the dielectric albedo table's loops took the Whitted scene's pipeline creation from 52 to 47 ms).
#extension GL_EXT_control_flow_attributes : require
#define VKRT_UNROLL [[unroll]]

#endif

#endif  // VKRT_SHADING_LANGUAGE_H
