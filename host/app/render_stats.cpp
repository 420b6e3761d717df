#include "app/render_stats.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "common/atomic_file.h"

namespace vkrt {

nlohmann::json toJson(const RunReport& r) {
    const double seconds = r.renderMs / 1000.0;
    nlohmann::json json = {
        {"scene", r.scene},
        {"device", r.device},
        {"camera", r.camera},
        {"triangles", r.triangles},
        {"spheres", r.spheres},
        {"solids", r.solids},
        {"shapes", r.shapes},
        {"texture_bytes", r.textureBytes},
        {"width", r.settings.width},
        {"height", r.settings.height},
        {"spp", r.samplesRendered},
        {"spp_max", r.mostSamplesRendered},
        {"interrupted", r.stopped == StopReason::Requested},
        {"stopped_by_time_limit", r.stopped == StopReason::TimeLimit},
        {"spp_requested", r.settings.samplesPerPixel},
        {"integrator", integratorName(r.settings.integrator)},
        {"max_depth", r.settings.maxDepth},
        {"light_samples", r.settings.lightSamples},
        {"seed", r.settings.seed},
        {"load_ms", r.loadMs},
        {"bvh",
         {{"build_ms", r.bvh.buildMs},
          {"nodes", r.bvh.nodes},
          {"leaves", r.bvh.leaves},
          {"depth", r.bvh.depth},
          {"sah_cost", r.bvh.sahCost}}},
        {"render_ms", r.renderMs},
        {"rays", {{"primary", r.rays.primary}, {"shadow", r.rays.shadow}, {"secondary", r.rays.secondary}}},
        {"mrays_per_s", seconds > 0.0 ? static_cast<double>(r.rays.total()) / seconds / 1e6 : 0.0},
        {"nonfinite_samples", r.rays.nonFiniteSamples},
        {"device_lost", r.stopped == StopReason::DeviceLost},
        {"memory",
         {{"host_estimate_bytes", r.memory.hostEstimateBytes},
          {"host_available_bytes", r.memory.hostAvailableBytes},
          {"host_peak_bytes", r.memory.hostPeakBytes},
          {"host_huge_page_bytes", r.memory.hostHugePageBytes}}},
    };
    if (!r.deviceLost.empty()) json["device_lost_because"] = r.deviceLost;
    if (r.environment) {
        const RunReport::Environment& e = *r.environment;
        if (e.uniformRadiance) {
            const glm::dvec3 u = *e.uniformRadiance;
            json["environment"] = {{"uniform_radiance", {u.x, u.y, u.z}}};
        } else {
            json["environment"] = {{"file", e.file},
                                   {"width", e.width},
                                   {"height", e.height},
                                   {"rotation_degrees", e.rotationDegrees},
                                   {"strength", e.strength}};
        }
    }
    json["ranks"] = std::max<size_t>(1, r.ranks.size());
    if (!r.ranks.empty()) {
        nlohmann::json perRank = nlohmann::json::array();
        for (size_t i = 0; i < r.ranks.size(); ++i) {
            const RunReport::Rank& k = r.ranks[i];
            perRank.push_back(
                {{"rank", i},
                 {"device", k.device},
                 {"device_name", k.deviceName},
                 {"spp", k.samples},
                 {"spp_max", k.samplesMax},
                 {"batches", k.batches},
                 {"rays",
                  {{"primary", k.rays.primary}, {"shadow", k.rays.shadow}, {"secondary", k.rays.secondary}}},
                 {"render_ms", k.renderMs}});
        }
        json["per_rank"] = perRank;
    }
    if (r.gpu) {
        const RunReport::Gpu& g = *r.gpu;
        json["device_name"] = g.deviceName;
        json["device_type"] = g.deviceType;
        json["driver"] = g.driver;
        json["gpu_ms"] = g.gpuMs;
        // The rays of the GPU timed: under MPI, rank 0's own (its figures are these), not the job's.
        const RayCounters& timedRays = r.ranks.empty() ? r.rays : r.ranks.front().rays;
        json["mrays_per_gpu_s"] =
            g.gpuMs > 0.0 ? static_cast<double>(timedRays.total()) / g.gpuMs / 1e3 : 0.0;
        json["features"] = g.features;
        json["scene_access"] = g.sceneAccess;
        json["gpu_memory_bytes"] = g.deviceMemoryBytes;
        json["memory"]["device_estimate_bytes"] = r.memory.deviceEstimateBytes;
        json["memory"]["device_budget_bytes"] = r.memory.deviceBudgetBytes;
        json["memory"]["tiles"] = r.memory.tiles;
        json["memory"]["tile_rows"] = r.memory.tileRows;
        json["memory"]["host_copies"] = r.memory.hostCopies;
        json["memory"]["host_copy_ms"] = g.hostCopyMs;
        json["setup"] = {{"total_ms", g.setupMs}, {"pack_ms", g.packMs}, {"scene_write_ms", g.sceneWriteMs}};
        json["shader"] = {{"features", g.allFeatures ? "all" : "scene"},
                          {"compile_ms", g.compileMs},
                          {"from_cache", g.shaderFromCache},
                          {"pipeline_ms", g.pipelineMs},
                          {"spirv_bytes", g.spirvBytes},
                          {"key", g.shaderKey}};
        json["dispatches"] = {{"count", g.dispatches},
                              {"longest_ms", g.longestDispatchMs},
                              {"total_ms", g.dispatchWallMs},
                              {"target_ms", g.targetDispatchMs},
                              {"most_samples", g.mostSamplesInDispatch},
                              {"loop_passes_per_sample", g.loopPassesPerSample},
                              {"workgroup_order", g.workgroupOrder}};
    }
    return json;
}

void writeJson(const nlohmann::json& json, const std::string& path) {
    FileBatch batch;
    stageJson(batch, json, path);
    batch.commit();
}

void stageJson(FileBatch& batch, const nlohmann::json& json, const std::string& path) {
    batch.stage(path, [&](const std::string& temporary) {
        std::ofstream file(temporary);
        // Names in it (paths) need not be UTF-8 on Linux: bytes that are not become U+FFFD rather than an
        // error.
        file << json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        file.close();  // a failed write may show only when the last bytes go out
        if (file.fail()) throw std::runtime_error(cannotWrite(path));
    });
}

}  // namespace vkrt
