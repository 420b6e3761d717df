// Error against run time in a vkrt run (--report, --reference): the reference, read from a file or rendered
// by the run itself, and at the end the report written and its last error said in one line.
#pragma once

#include <string>

#include "app/convergence_report.h"
#include "app/options.h"
#include "app/render_stats.h"
#include "common/render_settings.h"

namespace vkrt {

class FileBatch;

// The --reference image, checked against the render's size; UsageError when it cannot be used.
ConvergenceReport referenceFromFile(const Options& options, const RenderSettings& settings);

// The settings of the reference a run renders for --report without --reference: another seed and 16 times
// the samples of the render.
RenderSettings referenceRenderSettings(const RenderSettings& settings);

// Where that reference comes from, as the report names it (said on stderr unless --quiet): a render on the
// GPU or the CPU (`device`: "gpu", "cpu", or "gpu and cpu" for a job with both), by one process or by `ranks`
// ranks.
std::string announceRenderedReference(const Options& options, const RenderSettings& referenceSettings,
                                      const std::string& device, int ranks);

// Writes the --report file into `batch`, when asked (its context names the ranks when there are several), and
// sums up the last checkpoint's error in one line unless --quiet or not `summarise` (a render that failed:
// the last checkpoint is not the image written).
void writeConvergence(FileBatch& batch, const Options& options, const ConvergenceReport& convergence,
                      const RunReport& report, const RenderSettings& settings, int ranks,
                      bool summarise = true);

}  // namespace vkrt
