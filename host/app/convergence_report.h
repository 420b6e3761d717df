// Error against run time: at checkpoints of a progressive render, the samples so far, the render and GPU
// time, and the error against a reference image (RMSE, relMSE, fraction of pixels off by more than 1%).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"

namespace vkrt {

class FileBatch;

struct ConvergencePoint {
    uint32_t samples = 0;
    double renderMs = 0.0;
    double gpuMs = 0.0;
    double rmse = 0.0;
    double relMse = 0.0;
    double fractionOff = 0.0;
};

class ConvergenceReport {
  public:
    // `source` says where the reference came from (a file, or a render this run made).
    ConvergenceReport(Image reference, std::string source);

    void add(uint32_t samples, double renderMs, double gpuMs, const Image& image);
    const std::vector<ConvergencePoint>& points() const { return points_; }

    // Writes CSV (a header row, then one row per checkpoint) for a .csv path, JSON otherwise; `context`
    // (scene, device, settings) goes into the JSON. Written under a temporary name that `batch` renames into
    // place with the files written beside it.
    void write(FileBatch& batch, const std::string& path, const nlohmann::json& context) const;

  private:
    Image reference_;
    std::string source_;
    std::vector<ConvergencePoint> points_;
};

}  // namespace vkrt
