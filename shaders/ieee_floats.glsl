// Where the device offers it (VKRT_IEEE_FLOATS, from VkPhysicalDeviceVulkan12Properties'
// shaderSignedZeroInfNanPreserveFloat32), a kernel asks for IEEE 754's signed zeros, infinities and NaNs in
// single precision (SPIR-V's SignedZeroInfNanPreserve execution mode). Without it Vulkan lets a compiler assume
// there are none, and the guards the shading code shares with the CPU reference count on them: a NaN failing
// `x > 0.0`, an infinite density, a -0 that compares as 0 (on an H200 the sign of zero chose orthonormalBasis's
// branch until it parted below -1e-30). Included before any declaration, as #extension must be.
#ifndef VKRT_IEEE_FLOATS_GLSL
#define VKRT_IEEE_FLOATS_GLSL
#ifdef VKRT_IEEE_FLOATS
#extension GL_EXT_spirv_intrinsics : require
spirv_execution_mode(capabilities = [4466], 4461, 32);  // capability and mode SignedZeroInfNanPreserve, 32 bits
#endif
#endif
