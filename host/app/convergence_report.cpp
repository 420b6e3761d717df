#include "app/convergence_report.h"

#include <cmath>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/file_names.h"
#include "image/image_metrics.h"

namespace vkrt {

ConvergenceReport::ConvergenceReport(Image reference, std::string source)
    : reference_(std::move(reference)), source_(std::move(source)) {}

void ConvergenceReport::add(uint32_t samples, double renderMs, double gpuMs, const Image& image) {
    if (image.width != reference_.width || image.height != reference_.height) {
        throw std::runtime_error("the reference is " + std::to_string(reference_.width) + "x" +
                                 std::to_string(reference_.height) + " but the render is " +
                                 std::to_string(image.width) + "x" + std::to_string(image.height));
    }
    const ImageDifference d = compareImages(image, reference_, 0.01, 1e-3);
    points_.push_back({samples, renderMs, gpuMs, d.rmse, d.relMse, d.fractionOff});
}

void ConvergenceReport::write(FileBatch& batch, const std::string& path,
                              const nlohmann::json& context) const {
    const bool csv = lowerExtension(path) == ".csv";
    batch.stage(path, [&](const std::string& temporary) {
        std::ofstream out(temporary);
        if (csv) {
            out << "samples,render_ms,gpu_ms,rmse,relmse,fraction_off_1pct\n";
            for (const ConvergencePoint& p : points_) {
                out << p.samples << "," << p.renderMs << ",";
                if (std::isfinite(p.gpuMs)) out << p.gpuMs;  // empty where unknown (ranks of a job)
                out << "," << p.rmse << "," << p.relMse << "," << p.fractionOff << "\n";
            }
        } else {
            nlohmann::json json = context;
            json["reference"] = source_;
            json["checkpoints"] = nlohmann::json::array();
            for (const ConvergencePoint& p : points_) {
                json["checkpoints"].push_back(
                    {{"samples", p.samples},
                     {"render_ms", p.renderMs},
                     {"gpu_ms", std::isfinite(p.gpuMs) ? nlohmann::json(p.gpuMs) : nlohmann::json(nullptr)},
                     {"rmse", p.rmse},
                     {"relmse", p.relMse},
                     {"fraction_off_1pct", p.fractionOff}});
            }
            out << json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
                << "\n";  // paths need not be UTF-8
        }
        out.close();  // a failed write may show only when the last bytes go out
        if (out.fail()) throw std::runtime_error(cannotWrite(path));
    });
}

}  // namespace vkrt
