// The statistics JSON written by --stats.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "bvh/bvh.h"
#include "common/render_settings.h"

namespace vkrt {

struct RunReport {
    std::string scene;
    std::string device;
    std::string camera;
    size_t triangles = 0;
    RenderSettings settings;
    BvhStats bvh;
    double loadMs = 0.0;
    double renderMs = 0.0;
    RayCounters rays;
};

nlohmann::json toJson(const RunReport& report);

// Writes the JSON atomically (a temporary file renamed into place).
void writeJson(const nlohmann::json& json, const std::string& path);

}  // namespace vkrt
