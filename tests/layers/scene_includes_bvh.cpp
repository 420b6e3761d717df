// Deliberately wrong: the scene layer must not see the BVH above it. Built against vkrt_scene alone, the
// include must fail (Layers.WrongWayIncludeFailsToBuild).
#include "scene/scene.h"
#include "bvh/flat_bvh.h"
