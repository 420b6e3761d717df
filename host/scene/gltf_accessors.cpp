#include "scene/gltf_accessors.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <sstream>

#include <tiny_gltf.h>

#include "scene/scene_error.h"

namespace vkrt {
double normalizedValue(double stored, int componentType, bool normalized) {
    if (!normalized) return stored;
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return std::max(stored / 127.0, -1.0);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return stored / 255.0;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return std::max(stored / 32767.0, -1.0);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return stored / 65535.0;
        default:
            return stored;
    }
}

namespace {

int componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT2:
            return 4;
        case TINYGLTF_TYPE_MAT3:
            return 9;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

// One component, converted to double; normalized integers follow glTF 2.0 section 3.11.
double decodeComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            int8_t v;
            std::memcpy(&v, p, 1);
            return normalizedValue(v, componentType, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return normalizedValue(p[0], componentType, normalized);
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return normalizedValue(v, componentType, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return normalizedValue(v, componentType, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        default: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

// A strided run of elements inside one buffer view, every byte of it checked to exist.
struct ElementRun {
    const unsigned char* data = nullptr;
    size_t stride = 0;
};

}  // namespace

AccessorReader::AccessorReader(const tinygltf::Model& model, std::string file)
    : model_(model), file_(std::move(file)) {
    for (const std::string& name : model.extensionsUsed) quantized_ |= name == "KHR_mesh_quantization";
    for (const std::string& name : model.extensionsRequired) quantized_ |= name == "KHR_mesh_quantization";
}

void AccessorReader::fail(const std::string& message) const {
    throw SceneError(file_ + ": " + message);
}

size_t AccessorReader::count(int accessorIndex, const std::string& what) const {
    if (accessorIndex < 0 || accessorIndex >= static_cast<int>(model_.accessors.size())) {
        fail(what + " refers to accessor " + std::to_string(accessorIndex) + ", which does not exist");
    }
    return model_.accessors[accessorIndex].count;
}

namespace {

constexpr size_t kMaxSparseOnlyElements = size_t{1} << 26;

}  // namespace

std::vector<double> AccessorReader::readComponents(int accessorIndex, int components, bool wantIndices,
                                                   const std::string& what, size_t firstElements,
                                                   size_t step) const {
    const size_t accessorCount = count(accessorIndex, what);
    // The elements read: 0, step, 2 step, ..., at most firstElements of them.
    const size_t elementCount = std::min(accessorCount / step + (accessorCount % step != 0), firstElements);
    const tinygltf::Accessor& accessor = model_.accessors[accessorIndex];
    const std::string name = "accessor " + std::to_string(accessorIndex) + " (" + what + ")";

    const int size = componentSize(accessor.componentType);
    if (size == 0) fail(name + " has an invalid componentType " + std::to_string(accessor.componentType));
    if (componentCount(accessor.type) != components) {
        fail(name + " has " + std::to_string(componentCount(accessor.type)) + " components per element, " +
             std::to_string(components) + " expected");
    }
    if (wantIndices && (accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                        accessor.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                        accessor.componentType == TINYGLTF_COMPONENT_TYPE_SHORT || accessor.normalized)) {
        fail(name + " must use an unsigned integer component type, not normalized");
    }
    if (!wantIndices && accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !accessor.normalized) {
        if (!quantized_) fail(name + " must be FLOAT or normalized integers (or use KHR_mesh_quantization)");
        if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
            fail(name + " must be FLOAT or 8- or 16-bit integers");
        }
    }
    const size_t elementSize = static_cast<size_t>(size) * components;

    // Locates `n` elements of `elementSize` bytes at `byteOffset` inside buffer view `viewIndex`.
    auto locate = [&](int viewIndex, size_t byteOffset, size_t n, size_t elemSize,
                      const std::string& label) -> ElementRun {
        if (viewIndex < 0 || viewIndex >= static_cast<int>(model_.bufferViews.size())) {
            fail(label + " refers to bufferView " + std::to_string(viewIndex) + ", which does not exist");
        }
        const tinygltf::BufferView& view = model_.bufferViews[viewIndex];
        if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
            fail("bufferView " + std::to_string(viewIndex) + " refers to buffer " +
                 std::to_string(view.buffer) + ", which does not exist");
        }
        const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
        if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset) {
            std::ostringstream s;
            s << "bufferView " << viewIndex << " needs bytes [" << view.byteOffset << ", "
              << view.byteOffset + view.byteLength << ") but buffer " << view.buffer << " holds only "
              << buffer.data.size() << " bytes";
            fail(s.str());
        }
        const size_t stride = view.byteStride != 0 ? view.byteStride : elemSize;
        if (stride < elemSize) {
            fail("bufferView " + std::to_string(viewIndex) + " has byteStride " + std::to_string(stride) +
                 ", smaller than the " + std::to_string(elemSize) + "-byte elements of " + label);
        }
        if (n > 0) {
            // Last byte needed: byteOffset + stride * (n - 1) + elemSize, computed without overflow.
            const size_t available = view.byteLength;
            bool fits = byteOffset <= available && elemSize <= available - byteOffset &&
                        (n - 1) <= (available - byteOffset - elemSize) / stride;
            if (!fits) {
                std::ostringstream s;
                s << label << " overflows bufferView " << viewIndex << ": " << n << " elements of "
                  << elemSize << " bytes, stride " << stride << ", at offset " << byteOffset
                  << " need more than its " << available << " bytes";
                fail(s.str());
            }
        }
        return {buffer.data.data() + view.byteOffset + byteOffset, stride};
    };

    // The data is located, and its size checked, before anything is allocated for it. Only an accessor
    // with sparse values alone has no data to bound its count.
    std::optional<ElementRun> run;
    if (accessor.bufferView >= 0) {
        // Bounds checked up to the last element read.
        const size_t span = elementCount == 0 ? 0 : (elementCount - 1) * step + 1;
        run = locate(accessor.bufferView, accessor.byteOffset, span, elementSize, name);
        run->stride *= step;
    } else if (elementCount > kMaxSparseOnlyElements) {
        fail(name + " has " + std::to_string(elementCount) + " elements and no bufferView; vkrt reads at most " +
             std::to_string(kMaxSparseOnlyElements) + " such");
    }
    std::vector<double> values(elementCount * components, 0.0);
    if (run) {
        for (size_t i = 0; i < elementCount; ++i) {
            const unsigned char* element = run->data + i * run->stride;
            for (int c = 0; c < components; ++c) {
                values[i * components + c] =
                    decodeComponent(element + c * size, accessor.componentType, accessor.normalized);
            }
        }
    } else if (!accessor.sparse.isSparse) {
        fail(name + " has neither a bufferView nor sparse values");
    }

    // Sparse accessors replace some elements of the base values (glTF 2.0 section 3.6.2.3).
    if (accessor.sparse.isSparse) {
        const auto& sparse = accessor.sparse;
        const size_t n = static_cast<size_t>(sparse.count);
        if (sparse.count < 1 || n > accessorCount) fail(name + " has an invalid sparse count");
        const int indexSize = componentSize(sparse.indices.componentType);
        if (indexSize == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
            fail(name + " has an invalid sparse index component type");
        }
        ElementRun indices = locate(sparse.indices.bufferView, sparse.indices.byteOffset, n, indexSize,
                                    name + " sparse indices");
        ElementRun replacements = locate(sparse.values.bufferView, sparse.values.byteOffset, n, elementSize,
                                         name + " sparse values");
        indices.stride = indexSize;  // sparse data is tightly packed
        replacements.stride = elementSize;
        for (size_t i = 0; i < n; ++i) {
            const double target =
                decodeComponent(indices.data + i * indexSize, sparse.indices.componentType, false);
            if (target >= static_cast<double>(accessorCount)) {
                fail(name + " has a sparse index " + std::to_string(static_cast<uint64_t>(target)) +
                     " out of range");
            }
            const size_t element = static_cast<size_t>(target);
            if (element % step != 0 || element / step >= elementCount) continue;  // not among those read
            const size_t at = element / step;
            for (int c = 0; c < components; ++c) {
                values[at * components + c] = decodeComponent(replacements.data + i * elementSize + c * size,
                                                              accessor.componentType, accessor.normalized);
            }
        }
    }
    return values;
}

std::vector<float> AccessorReader::readFloats(int accessorIndex, int components, const std::string& what,
                                              size_t firstElements) const {
    std::vector<double> values = readComponents(accessorIndex, components, false, what, firstElements);
    std::vector<float> result(values.size());
    for (size_t i = 0; i < values.size(); ++i) result[i] = static_cast<float>(values[i]);
    return result;
}

std::vector<float> AccessorReader::sampleFloats(int accessorIndex, int components, const std::string& what,
                                                size_t maxElements) const {
    const size_t n = count(accessorIndex, what);
    const size_t step = n <= maxElements ? 1 : n / maxElements + (n % maxElements != 0);
    std::vector<double> values = readComponents(accessorIndex, components, false, what, SIZE_MAX, step);
    return std::vector<float>(values.begin(), values.end());
}

std::vector<uint32_t> AccessorReader::readIndices(int accessorIndex, const std::string& what) const {
    return readUnsigned(accessorIndex, 1, what);
}

std::vector<uint32_t> AccessorReader::readUnsigned(int accessorIndex, int components,
                                                   const std::string& what) const {
    std::vector<double> values = readComponents(accessorIndex, components, true, what);
    std::vector<uint32_t> result(values.size());
    for (size_t i = 0; i < values.size(); ++i) result[i] = static_cast<uint32_t>(values[i]);
    return result;
}

}  // namespace vkrt
