// Under mpirun: one rank's part in the render the ranks share (shared_render.h). Every rank renders its share
// on its own device; rank 0 sums the shares and writes the image, the stats and the report as one process
// would.
#pragma once

#include "app/mpi_job.h"
#include "app/options.h"
#include "app/prepared_render.h"
#include "app/render_stats.h"

namespace vkrt {

// This rank's share of the render `prepared` (every rank comes here with its own); returns the exit code.
// Collective. Throws UsageError when the ranks were not given the same render, InterruptedBeforeRender
// (rank 0) when a signal ended the reference of --report.
int renderShared(const MpiJob& job, const Options& options, const PreparedRender& prepared,
                 RunReport& report);

}  // namespace vkrt
