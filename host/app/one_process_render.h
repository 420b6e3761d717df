// The render by one process (no MPI job, or a job of one): on the chosen device, with the reference of
// --report made first when there is no --reference; then the image, the stats and the report.
#pragma once

#include "app/options.h"
#include "app/prepared_render.h"
#include "app/render_stats.h"

namespace vkrt {

// Renders `prepared` and writes what `options` ask for; returns the exit code (1 when the GPU device was
// lost, 128 + N when signal N stopped the render). Throws InterruptedBeforeRender when a signal ended the
// reference of --report.
int renderOneProcess(const Options& options, const PreparedRender& prepared, RunReport& report);

}  // namespace vkrt
