// Deliberately wrong: the CPU reference must not see the GPU layer. tests/CMakeLists.txt builds this file
// against vkrt_cpu alone and expects the include to fail (Layers.WrongWayIncludeFailsToBuild).
#include "cpu/reference_renderer.h"
#include "gpu/gpu_renderer.h"
