// The directional albedo table of KHR_materials_sheen's lobe (shaders/sheen.h), tabulated in double
// precision when vkrt is built (albedo_table_entries.h) and read by both renderers.
#pragma once

#include <vector>

namespace vkrt {

// VKRT_SHEEN_TABLE_SIZE^2 entries, laid out as sheen.h's sheenAlbedo reads them.
const std::vector<float>& sheenAlbedoTable();

}  // namespace vkrt
