#include "scene/sheen_table.h"

#include <iterator>

#include "scene/albedo_table_entries.h"

namespace vkrt {

const std::vector<float>& sheenAlbedoTable() {
    static const std::vector<float> table(std::begin(kSheenAlbedoTable), std::end(kSheenAlbedoTable));
    return table;
}

}  // namespace vkrt
