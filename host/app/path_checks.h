// The files a render reads and writes, checked before anything is loaded or rendered: a render of minutes must
// not end in "cannot write".
#pragma once

#include "app/options.h"

namespace vkrt {

// Throws UsageError (exit code 2), naming the option and the path, when the scene is missing, is a directory
// or cannot be read, or when the folder of the image, --stats or --report does not exist or cannot be written.
// (--environment and --reference are read, and checked, before rendering starts.)
void checkPaths(const Options& options);

}  // namespace vkrt
