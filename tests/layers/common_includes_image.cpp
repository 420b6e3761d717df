// Deliberately wrong: host/common is the bottom layer and must not see image/. Built against vkrt_common
// alone, the include must fail (Layers.WrongWayIncludeFailsToBuild).
#include "common/render_settings.h"
#include "image/image.h"
