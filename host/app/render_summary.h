// What a finished render reports, by one process or by the ranks of an MPI job: the stats' account of the
// scene, the settings and the result, the stats file, and the lines on stderr that sum the render up.
#pragma once

#include "app/options.h"
#include "app/render_stats.h"
#include "image/render_result.h"
#include "scene/scene.h"

namespace vkrt {

class FileBatch;

// What the stats say of the scene and the settings, whoever rendered it.
void describeRun(const Options& options, const Scene& scene, const RenderSettings& settings,
                 const Camera& camera, RunReport& report);

// The render's samples per pixel, why it stopped and its rays.
void recordResult(const RenderResult& result, RunReport& report);

// Records the process's peak resident memory and writes the --stats file into `batch`, when asked.
void writeStats(FileBatch& batch, const Options& options, RunReport& report);

// True, after one error line naming the scene, where samples were traced and every one was left out (not
// finite, beyond its pixel's single-precision sum, or past llvmpipe's loop budget), of the whole image or of
// pixels that all had samples traced: the image would be black there (an object whose every sample ran past
// the budget vanished, with exit 0 and a warning), so the caller writes nothing and exits with
// kExitRuntimeFailure.
bool samplesLeftOutOfWholePixels(const RenderResult& result, const std::string& scenePath);

// True, after one line, where an interrupt (SIGINT, SIGTERM, SIGHUP) stopped the render before every pixel
// had a sample: the image would have black holes (and replace whatever stood at its path), so the caller
// writes nothing and exits as the signal asks.
bool interruptedBeforeEveryPixel(const RenderResult& result);

// Unless --quiet: the line that says what was written, with the samples per pixel ("A to B" when the render
// stopped part way through a pass), the time and the rays per second; under MPI one more line per rank.
void printRenderSummary(const Options& options, const RunReport& report, int ranks);

}  // namespace vkrt
