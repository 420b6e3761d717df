// Reading glTF accessors with every bound checked: the buffer, the buffer view, the stride, the
// accessor's last element, sparse substitutions and index values. tinygltf parses the JSON but does not
// check that accessors stay inside their buffers; this does, and throws SceneError when they do not.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace vkrt {

// A component's value as the accessor means it: a normalized integer of `componentType` (glTF 2.0 section
// 3.11) mapped to [0, 1] or [-1, 1], anything else as it is. Also for an accessor's min and max, which the
// file gives as the stored integers (section 3.6.2.5: `normalized` has no effect on them).
double normalizedValue(double stored, int componentType, bool normalized);

class AccessorReader {
  public:
    AccessorReader(const tinygltf::Model& model, std::string file);

    // Reads `components` values per element (VEC2 = 2, VEC3 = 3, ...). Float accessors are read as they
    // are; normalized integer accessors are mapped to [0, 1] or [-1, 1] as the glTF spec says. Integers
    // that are not normalized are read as their values where the file uses KHR_mesh_quantization (whose
    // positions and texture coordinates are scaled back by the node's transform and the texture transform),
    // and refused otherwise.
    // Only the first `firstElements` elements where given (a skin's inverse bind matrices beyond its joints).
    std::vector<float> readFloats(int accessorIndex, int components, const std::string& what,
                                  size_t firstElements = SIZE_MAX) const;

    // At most `maxElements` elements spread evenly over the accessor (elements 0, k, 2k, ...), read as
    // readFloats reads them.
    std::vector<float> sampleFloats(int accessorIndex, int components, const std::string& what,
                                    size_t maxElements) const;

    // Reads a scalar unsigned-integer accessor (mesh indices).
    std::vector<uint32_t> readIndices(int accessorIndex, const std::string& what) const;

    // Reads `components` unsigned integers per element (a skinned primitive's JOINTS_n).
    std::vector<uint32_t> readUnsigned(int accessorIndex, int components, const std::string& what) const;

    // The element count of an accessor, after checking that the index is valid.
    size_t count(int accessorIndex, const std::string& what) const;

  private:
    [[noreturn]] void fail(const std::string& message) const;
    std::vector<double> readComponents(int accessorIndex, int components, bool wantIndices,
                                       const std::string& what, size_t firstElements = SIZE_MAX,
                                       size_t step = 1) const;

    const tinygltf::Model& model_;
    std::string file_;
    bool quantized_ = false;  // the file uses KHR_mesh_quantization
};

}  // namespace vkrt
