#include "scene/gltf_schema.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene_error.h"

namespace vkrt {
namespace {

using Json = nlohmann::json;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kHalfPi = 1.57079632679489661923;

// A number as an error shows it: integers in full (4294967296, not 4.29497e+09), others to 6 digits.
std::string shown(double v) {
    if (std::trunc(v) == v && std::abs(v) < 0x1p63) return std::to_string(static_cast<int64_t>(v));
    std::ostringstream s;
    s << v;
    return s.str();
}

// The numbers a property may take: from `low` to `high`, each end closed unless marked open.
struct Range {
    double low = -kInfinity;
    double high = kInfinity;
    bool lowOpen = false;
    bool highOpen = false;

    bool contains(double v) const {
        return (lowOpen ? v > low : v >= low) && (highOpen ? v < high : v <= high);
    }
    std::string text() const {
        std::ostringstream s;
        if (high == kInfinity) {
            s << (lowOpen ? "> " : ">= ") << shown(low);
        } else {
            s << "in " << (lowOpen ? "(" : "[") << shown(low) << ", " << shown(high)
              << (highOpen ? ")" : "]");
        }
        return s.str();
    }
};

const Range kAny;
const Range kUnit{0.0, 1.0};
const Range kNonNegative{0.0};
const Range kPositive{0.0, kInfinity, true};
// tinygltf keeps some integers as 32-bit ints (every one of an extension's, and of the core's a texture's
// source, a texCoord, a sparse accessor's count and offsets), which wrap: 2^32 more than a valid value reads
// as that value. Such integers are held to an int's range.
const Range kNonNegativeInt{0.0, 2147483647.0};

std::string member(const std::string& where, const char* key) {
    return where.empty() ? key : where + "." + key;
}

std::string element(const std::string& where, size_t i) {
    return where + "[" + std::to_string(i) + "]";
}

// The properties vkrt reads, by glTF object, each checked for its JSON type, its range and, for an index,
// that it names an object of the file. The first violation throws, naming its JSON path.
class SchemaCheck {
public:
    SchemaCheck(const Json& root, std::string path) : root_(root), path_(std::move(path)) {}

    void document() {
        if (!root_.is_object()) fail("the document", "expected a JSON object");
        nesting();
        const Json& asset = requiredObject(root_, "asset", "");
        version(asset);
        for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
            if (const Json* names = array(root_, key, "")) {
                for (size_t i = 0; i < names->size(); ++i) {
                    if (!(*names)[i].is_string()) fail(element(key, i), "expected a string");
                }
            }
        }
        // Every top-level collection is an array of objects before any index into one is checked.
        for (const char* key : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images",
                                "materials", "meshes", "nodes", "samplers", "scenes", "skins", "textures"}) {
            eachObject(root_, key, "", [](const Json&, const std::string&) {});
        }
        lightCount_ = 0;
        if (const Json* extensions = object(root_, "extensions", "")) {
            if (const Json* lights = object(*extensions, "KHR_lights_punctual", "extensions")) {
                eachObject(*lights, "lights", "extensions.KHR_lights_punctual",
                           [&](const Json& light, const std::string& where) { this->light(light, where); });
                lightCount_ = (*lights).contains("lights") ? (*lights)["lights"].size() : 0;
            }
        }
        index(root_, "scene", "", "scenes", "scene");
        eachObject(root_, "scenes", "", [&](const Json& scene, const std::string& where) {
            name(scene, where);
            indices(scene, "nodes", where, "nodes", "node");
        });
        eachObject(root_, "nodes", "", [&](const Json& node, const std::string& where) { this->node(node, where); });
        eachObject(root_, "meshes", "", [&](const Json& mesh, const std::string& where) { this->mesh(mesh, where); });
        eachObject(root_, "skins", "", [&](const Json& skin, const std::string& where) {
            name(skin, where);
            index(skin, "inverseBindMatrices", where, "accessors", "accessor");
            index(skin, "skeleton", where, "nodes", "node");
            array(skin, "joints", where, true, 1);
            indices(skin, "joints", where, "nodes", "node");
        });
        eachObject(root_, "accessors", "",
                   [&](const Json& accessor, const std::string& where) { this->accessor(accessor, where); });
        eachObject(root_, "bufferViews", "", [&](const Json& view, const std::string& where) {
            index(view, "buffer", where, "buffers", "buffer", true);
            integer(view, "byteOffset", where, kNonNegative);
            integer(view, "byteLength", where, Range{1.0}, true);
            if (integer(view, "byteStride", where, Range{4.0, 252.0}) &&
                std::fmod(view["byteStride"].get<double>(), 4.0) != 0.0) {
                fail(member(where, "byteStride"), "expected a multiple of 4");
            }
            oneOf(view, "target", where, {34962, 34963});
            meshoptView(view, where);
        });
        eachObject(root_, "buffers", "", [&](const Json& buffer, const std::string& where) {
            string(buffer, "uri", where);
            integer(buffer, "byteLength", where, Range{1.0}, true);
            if (const Json* extensions = object(buffer, "extensions", where)) {
                const std::string at = member(where, "extensions");
                if (const Json* meshopt = object(*extensions, "EXT_meshopt_compression", at))
                    boolean(*meshopt, "fallback", member(at, "EXT_meshopt_compression"));
            }
        });
        // Every view inside its buffer (tinygltf reads an image's view without checking: found by fuzzing).
        eachObject(root_, "bufferViews", "", [&](const Json& view, const std::string& where) {
            const double offset = view.contains("byteOffset") ? view["byteOffset"].get<double>() : 0.0;
            const double end = offset + view["byteLength"].get<double>();
            const double size = root_["buffers"][view["buffer"].get<size_t>()]["byteLength"].get<double>();
            if (end > size) {
                fail(where, "bytes [" + std::to_string(std::llround(offset)) + ", " + std::to_string(std::llround(end)) +
                                ") lie outside buffer " + std::to_string(view["buffer"].get<size_t>()) + "'s " +
                                std::to_string(std::llround(size)));
            }
        });
        eachObject(root_, "images", "", [&](const Json& image, const std::string& where) {
            name(image, where);
            string(image, "uri", where);
            string(image, "mimeType", where);
            index(image, "bufferView", where, "bufferViews", "buffer view");
        });
        eachObject(root_, "textures", "", [&](const Json& texture, const std::string& where) {
            index(texture, "sampler", where, "samplers", "sampler");
            // Its image must exist only when a material uses it (textureInfo): files in the wild keep unused
            // textures that name nothing.
            integer(texture, "source", where, kNonNegativeInt);
            if (const Json* extensions = object(texture, "extensions", where)) {
                const std::string at = member(where, "extensions");
                if (const Json* webp = object(*extensions, "EXT_texture_webp", at))
                    integer(*webp, "source", member(at, "EXT_texture_webp"), kNonNegativeInt);
            }
        });
        eachObject(root_, "samplers", "", [&](const Json& sampler, const std::string& where) {
            oneOf(sampler, "magFilter", where, {9728, 9729});
            oneOf(sampler, "minFilter", where, {9728, 9729, 9984, 9985, 9986, 9987});
            oneOf(sampler, "wrapS", where, {33071, 33648, 10497});
            oneOf(sampler, "wrapT", where, {33071, 33648, 10497});
        });
        eachObject(root_, "materials", "",
                   [&](const Json& material, const std::string& where) { this->material(material, where); });
        eachObject(root_, "cameras", "", [&](const Json& camera, const std::string& where) { this->camera(camera, where); });
        eachObject(root_, "animations", "",
                   [&](const Json& animation, const std::string& where) { this->animation(animation, where); });
    }

private:
    [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
        throw SceneError(path_ + ": " + where + ": " + problem);
    }

    // tinygltf reads nested JSON values by recursion, one call a level, and a file nested 20,000 levels deep
    // (in extras, which it reads whole) overflows its stack. glTF itself needs a few levels.
    void nesting() const {
        constexpr size_t kMaxLevels = 512;
        std::vector<std::pair<const Json*, size_t>> pending{{&root_, 1}};
        while (!pending.empty()) {
            const auto [value, level] = pending.back();
            pending.pop_back();
            if (level > kMaxLevels)
                fail("the document", "JSON nested more than " + std::to_string(kMaxLevels) + " levels deep");
            if (value->is_structured()) {
                for (const Json& child : *value) pending.emplace_back(&child, level + 1);
            }
        }
    }

    // glTF 2.0, 3.5.1: a loader rejects an asset whose major version it does not read, or whose minVersion is
    // newer than what it reads (vkrt reads 2.0).
    void version(const Json& asset) const {
        string(asset, "version", "asset", true);
        const std::string version = asset["version"].get<std::string>();
        // <major>.<minor>, each a run of digits (checked by hand: std::regex recurses once a character).
        const size_t dot = version.find('.');
        const auto digits = [](const std::string& text) {
            return !text.empty() && text.size() <= 9 &&
                   std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
        };
        if (dot == std::string::npos || !digits(version.substr(0, dot)) || !digits(version.substr(dot + 1)))
            fail("asset.version", "expected <major>.<minor>, got " + shownText(version));
        if (version.substr(0, dot) != "2")
            fail("asset.version", "glTF " + version + " is not glTF 2.x, which vkrt reads");
        string(asset, "minVersion", "asset");
        if (const Json* minVersion = find(asset, "minVersion");
            minVersion && minVersion->get<std::string>() != "2.0")
            fail("asset.minVersion",
                 "requires glTF " + shownText(minVersion->get<std::string>()) + "; vkrt reads glTF 2.0");
    }

    // A string from the file as an error shows it: quoted and escaped (one line), cut short after 40 bytes.
    static std::string shownText(const std::string& text) {
        const std::string shown =
            Json(text.substr(0, 40)).dump(-1, ' ', false, Json::error_handler_t::replace);
        return text.size() > 40 ? shown + "..." : shown;
    }

    static const Json* find(const Json& parent, const char* key) {
        const auto it = parent.find(key);
        return it == parent.end() ? nullptr : &*it;
    }

    const Json* present(const Json& parent, const char* key, const std::string& where, bool required) const {
        const Json* value = find(parent, key);
        if (!value && required) fail(member(where, key), "missing, and required");
        return value;
    }

    const Json* object(const Json& parent, const char* key, const std::string& where, bool required = false) const {
        const Json* value = present(parent, key, where, required);
        if (value && !value->is_object()) fail(member(where, key), "expected an object");
        return value;
    }

    const Json& requiredObject(const Json& parent, const char* key, const std::string& where) const {
        return *object(parent, key, where, true);
    }

    const Json* array(const Json& parent, const char* key, const std::string& where, bool required = false,
                      size_t minItems = 0) const {
        const Json* value = present(parent, key, where, required);
        if (!value) return nullptr;
        if (!value->is_array()) fail(member(where, key), "expected an array");
        if (value->size() < minItems) {
            fail(member(where, key), "expected at least " + std::to_string(minItems) + " item(s)");
        }
        return value;
    }

    // Calls visit(item, path) for each item of the array parent[key], each of which must be an object.
    template <typename Visit>
    void eachObject(const Json& parent, const char* key, const std::string& where, Visit visit,
                    bool required = false, size_t minItems = 0) const {
        const Json* items = array(parent, key, where, required, minItems);
        if (!items) return;
        for (size_t i = 0; i < items->size(); ++i) {
            const std::string itemWhere = element(member(where, key), i);
            if (!(*items)[i].is_object()) fail(itemWhere, "expected an object");
            visit((*items)[i], itemWhere);
        }
    }

    void checkNumber(const Json& value, const std::string& where, const Range& range) const {
        if (!value.is_number()) fail(where, "expected a number");
        const double v = value.get<double>();
        if (!std::isfinite(v)) fail(where, "expected a finite number");
        // vkrt keeps a scene's numbers in single precision, where ones that round beyond its largest become
        // infinite (from FLT_MAX + half its last place, 2^128 - 2^103).
        if (std::abs(v) >= 0x1.ffffffp+127)
            fail(where, "expected a number within single precision's range, got " + shown(v));
        if (!range.contains(v)) fail(where, "expected a number " + range.text() + ", got " + shown(v));
    }

    bool number(const Json& parent, const char* key, const std::string& where, const Range& range,
                bool required = false) const {
        const Json* value = present(parent, key, where, required);
        if (value) checkNumber(*value, member(where, key), range);
        return value != nullptr;
    }

    void checkInteger(const Json& value, const std::string& where, const Range& range) const {
        if (!value.is_number() || std::trunc(value.get<double>()) != value.get<double>())
            fail(where, "expected an integer");
        checkNumber(value, where, range);
    }

    bool integer(const Json& parent, const char* key, const std::string& where, const Range& range,
                 bool required = false) const {
        const Json* value = present(parent, key, where, required);
        if (value) checkInteger(*value, member(where, key), range);
        return value != nullptr;
    }

    void oneOf(const Json& parent, const char* key, const std::string& where, std::initializer_list<int> allowed,
               bool required = false) const {
        const Json* value = present(parent, key, where, required);
        if (!value) return;
        checkInteger(*value, member(where, key), kAny);
        for (int a : allowed) {
            if (value->get<double>() == a) return;
        }
        std::string list;
        for (int a : allowed) list += (list.empty() ? "" : ", ") + std::to_string(a);
        fail(member(where, key), "expected one of " + list + ", got " + shown(value->get<double>()));
    }

    void numbers(const Json& parent, const char* key, const std::string& where, size_t count,
                 const Range& range) const {
        const Json* value = find(parent, key);
        if (!value) return;
        const std::string at = member(where, key);
        if (!value->is_array() || value->size() != count)
            fail(at, "expected an array of " + std::to_string(count) + " numbers");
        for (size_t i = 0; i < count; ++i) checkNumber((*value)[i], element(at, i), range);
    }

    void numberList(const Json& parent, const char* key, const std::string& where) const {
        const Json* value = array(parent, key, where);
        if (!value) return;
        for (size_t i = 0; i < value->size(); ++i) checkNumber((*value)[i], element(member(where, key), i), kAny);
    }

    void string(const Json& parent, const char* key, const std::string& where, bool required = false,
                std::initializer_list<const char*> allowed = {}) const {
        const Json* value = present(parent, key, where, required);
        if (!value) return;
        if (!value->is_string()) fail(member(where, key), "expected a string");
        if (allowed.size() == 0) return;
        std::string list;
        for (const char* a : allowed) {
            if (value->get<std::string>() == a) return;
            list += (list.empty() ? "\"" : ", \"") + std::string(a) + "\"";
        }
        fail(member(where, key), "expected one of " + list + ", got \"" + value->get<std::string>() + "\"");
    }

    void boolean(const Json& parent, const char* key, const std::string& where) const {
        const Json* value = find(parent, key);
        if (value && !value->is_boolean()) fail(member(where, key), "expected true or false");
    }

    void name(const Json& object, const std::string& where) const { string(object, "name", where); }

    size_t count(const char* collection) const {
        const Json* items = find(root_, collection);
        return items ? items->size() : 0;
    }

    void checkIndex(const Json& value, const std::string& where, size_t available, const char* singular) const {
        checkInteger(value, where, kNonNegative);
        const double i = value.get<double>();
        if (i >= static_cast<double>(available)) {
            fail(where, std::string(singular) + " " + shown(i) + " does not exist (the file has " +
                            std::to_string(available) + ")");
        }
    }

    // parent[key], when present, names an object of the top-level array `collection`.
    void index(const Json& parent, const char* key, const std::string& where, const char* collection,
               const char* singular, bool required = false) const {
        const Json* value = present(parent, key, where, required);
        if (value) checkIndex(*value, member(where, key), count(collection), singular);
    }

    void indices(const Json& parent, const char* key, const std::string& where, const char* collection,
                 const char* singular) const {
        const Json* values = array(parent, key, where);
        if (!values) return;
        for (size_t i = 0; i < values->size(); ++i)
            checkIndex((*values)[i], element(member(where, key), i), count(collection), singular);
    }

    // An object whose every member names an accessor (a primitive's attributes, a morph target).
    void accessorMap(const Json& map, const std::string& where) const {
        for (auto it = map.begin(); it != map.end(); ++it)
            checkIndex(it.value(), where + "." + it.key(), count("accessors"), "accessor");
    }

    void node(const Json& node, const std::string& where) const {
        name(node, where);
        index(node, "camera", where, "cameras", "camera");
        index(node, "mesh", where, "meshes", "mesh");
        index(node, "skin", where, "skins", "skin");
        indices(node, "children", where, "nodes", "node");
        numbers(node, "matrix", where, 16, kAny);
        numbers(node, "rotation", where, 4, Range{-1.0, 1.0});
        numbers(node, "scale", where, 3, kAny);
        numbers(node, "translation", where, 3, kAny);
        numberList(node, "weights", where);
        const Json* extensions = object(node, "extensions", where);
        if (!extensions) return;
        const std::string at = member(where, "extensions");
        if (const Json* light = object(*extensions, "KHR_lights_punctual", at)) {
            const std::string lightWhere = member(at, "KHR_lights_punctual");
            const Json* value = present(*light, "light", lightWhere, true);
            checkIndex(*value, member(lightWhere, "light"), lightCount_, "light");
        }
        if (const Json* instancing = object(*extensions, "EXT_mesh_gpu_instancing", at)) {
            const std::string instancingWhere = member(at, "EXT_mesh_gpu_instancing");
            accessorMap(requiredObject(*instancing, "attributes", instancingWhere),
                        member(instancingWhere, "attributes"));
        }
        if (const Json* sphere = object(*extensions, "VKRT_sphere", at)) {
            const std::string sphereWhere = member(at, "VKRT_sphere");
            number(*sphere, "radius", sphereWhere, kPositive, true);
            index(*sphere, "material", sphereWhere, "materials", "material");
        }
        if (const Json* shape = object(*extensions, "VKRT_shape", at)) {
            const std::string shapeWhere = member(at, "VKRT_shape");
            string(*shape, "shape", shapeWhere, true, {"sphere", "box", "cylinder", "cone"});
            index(*shape, "material", shapeWhere, "materials", "material");
        }
        if (const Json* csg = object(*extensions, "VKRT_csg", at)) {
            string(*csg, "operation", member(at, "VKRT_csg"), true, {"union", "intersection", "difference"});
        }
    }

    void mesh(const Json& mesh, const std::string& where) const {
        name(mesh, where);
        numberList(mesh, "weights", where);
        eachObject(
            mesh, "primitives", where,
            [&](const Json& primitive, const std::string& primitiveWhere) {
                accessorMap(requiredObject(primitive, "attributes", primitiveWhere),
                            member(primitiveWhere, "attributes"));
                index(primitive, "indices", primitiveWhere, "accessors", "accessor");
                index(primitive, "material", primitiveWhere, "materials", "material");
                oneOf(primitive, "mode", primitiveWhere, {0, 1, 2, 3, 4, 5, 6});
                dracoPrimitive(primitive, primitiveWhere);
                eachObject(primitive, "targets", primitiveWhere,
                           [&](const Json& target, const std::string& targetWhere) { accessorMap(target, targetWhere); });
            },
            true, 1);
    }

    // `owner`'s extension `name`, which must be an object, or null when it has none; `at` names where it
    // lies.
    const Json* extension(const Json& owner, const char* name, const std::string& where,
                          std::string& at) const {
        const Json* extensions = object(owner, "extensions", where);
        if (!extensions) return nullptr;
        at = member(member(where, "extensions"), name);
        return object(*extensions, name, member(where, "extensions"));
    }

    // EXT_meshopt_compression on a buffer view: where its compressed bytes are and what they decode to (the
    // codec's values, mode and filter, are checked as the view is decoded).
    void meshoptView(const Json& view, const std::string& where) const {
        std::string at;
        const Json* meshopt = extension(view, "EXT_meshopt_compression", where, at);
        if (!meshopt) return;
        index(*meshopt, "buffer", at, "buffers", "buffer", true);
        integer(*meshopt, "byteOffset", at, kNonNegativeInt);
        integer(*meshopt, "byteLength", at, kNonNegativeInt, true);
        integer(*meshopt, "byteStride", at, kNonNegativeInt, true);
        integer(*meshopt, "count", at, kNonNegativeInt, true);
        string(*meshopt, "mode", at, true);
        string(*meshopt, "filter", at);
    }

    // KHR_draco_mesh_compression on a primitive: the buffer view of its compressed data, and the Draco
    // attribute id of each attribute it holds.
    void dracoPrimitive(const Json& primitive, const std::string& where) const {
        std::string at;
        const Json* draco = extension(primitive, "KHR_draco_mesh_compression", where, at);
        if (!draco) return;
        index(*draco, "bufferView", at, "bufferViews", "buffer view", true);
        const Json& attributes = requiredObject(*draco, "attributes", at);
        for (auto it = attributes.begin(); it != attributes.end(); ++it)
            checkInteger(it.value(), member(member(at, "attributes"), it.key().c_str()), kNonNegativeInt);
    }

    void accessor(const Json& accessor, const std::string& where) const {
        name(accessor, where);
        index(accessor, "bufferView", where, "bufferViews", "buffer view");
        integer(accessor, "byteOffset", where, kNonNegative);
        oneOf(accessor, "componentType", where, {5120, 5121, 5122, 5123, 5125, 5126}, true);
        boolean(accessor, "normalized", where);
        integer(accessor, "count", where, Range{1.0}, true);
        string(accessor, "type", where, true, {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"});
        numberList(accessor, "min", where);
        numberList(accessor, "max", where);
        const Json* sparse = object(accessor, "sparse", where);
        if (!sparse) return;
        const std::string sparseWhere = member(where, "sparse");
        integer(*sparse, "count", sparseWhere, Range{1.0, kNonNegativeInt.high}, true);
        const Json& sparseIndices = requiredObject(*sparse, "indices", sparseWhere);
        const std::string indicesWhere = member(sparseWhere, "indices");
        index(sparseIndices, "bufferView", indicesWhere, "bufferViews", "buffer view", true);
        integer(sparseIndices, "byteOffset", indicesWhere, kNonNegativeInt);
        oneOf(sparseIndices, "componentType", indicesWhere, {5121, 5123, 5125}, true);
        const Json& values = requiredObject(*sparse, "values", sparseWhere);
        index(values, "bufferView", member(sparseWhere, "values"), "bufferViews", "buffer view", true);
        integer(values, "byteOffset", member(sparseWhere, "values"), kNonNegativeInt);
    }

    // A textureInfo: which texture, which coordinates, and their KHR_texture_transform.
    void textureInfo(const Json& parent, const char* key, const std::string& where) const {
        const Json* info = object(parent, key, where);
        if (!info) return;
        const std::string at = member(where, key);
        index(*info, "index", at, "textures", "texture", true);
        const Json& texture = root_["textures"][(*info)["index"].get<size_t>()];
        if (const Json* source = find(texture, "source"))
            checkIndex(*source, member(at, "index") + " (its texture's source)", count("images"), "image");
        const Json* textureExtensions = find(texture, "extensions");
        if (const Json* webp = textureExtensions ? find(*textureExtensions, "EXT_texture_webp") : nullptr) {
            if (const Json* source = find(*webp, "source"))
                checkIndex(*source, member(at, "index") + " (its texture's WebP source)", count("images"),
                           "image");
        }
        integer(*info, "texCoord", at, kNonNegativeInt);
        number(*info, "scale", at, kAny);            // normal textures
        number(*info, "strength", at, kUnit);        // occlusion textures
        const Json* extensions = object(*info, "extensions", at);
        if (!extensions) return;
        const Json* transform = object(*extensions, "KHR_texture_transform", member(at, "extensions"));
        if (!transform) return;
        const std::string transformWhere = member(at, "extensions.KHR_texture_transform");
        numbers(*transform, "offset", transformWhere, 2, kAny);
        number(*transform, "rotation", transformWhere, kAny);
        numbers(*transform, "scale", transformWhere, 2, kAny);
        integer(*transform, "texCoord", transformWhere, kNonNegativeInt);
    }

    void material(const Json& material, const std::string& where) const {
        name(material, where);
        if (const Json* pbr = object(material, "pbrMetallicRoughness", where)) {
            const std::string pbrWhere = member(where, "pbrMetallicRoughness");
            numbers(*pbr, "baseColorFactor", pbrWhere, 4, kUnit);
            textureInfo(*pbr, "baseColorTexture", pbrWhere);
            number(*pbr, "metallicFactor", pbrWhere, kUnit);
            number(*pbr, "roughnessFactor", pbrWhere, kUnit);
            textureInfo(*pbr, "metallicRoughnessTexture", pbrWhere);
        }
        textureInfo(material, "normalTexture", where);
        textureInfo(material, "occlusionTexture", where);
        textureInfo(material, "emissiveTexture", where);
        // glTF says [0, 1]; files made before KHR_materials_emissive_strength write brighter lights as larger
        // factors, and vkrt renders them as written.
        numbers(material, "emissiveFactor", where, 3, kNonNegative);
        string(material, "alphaMode", where, false, {"OPAQUE", "MASK", "BLEND"});
        number(material, "alphaCutoff", where, kNonNegative);
        boolean(material, "doubleSided", where);
        const Json* extensions = object(material, "extensions", where);
        if (!extensions) return;
        const std::string at = member(where, "extensions");
        auto extension = [&](const char* name, auto check) {
            if (const Json* value = object(*extensions, name, at)) check(*value, member(at, name));
        };
        extension("KHR_materials_emissive_strength", [&](const Json& e, const std::string& w) {
            number(e, "emissiveStrength", w, kNonNegative);
        });
        extension("KHR_materials_transmission", [&](const Json& e, const std::string& w) {
            number(e, "transmissionFactor", w, kUnit);
            textureInfo(e, "transmissionTexture", w);
        });
        extension("KHR_materials_ior", [&](const Json& e, const std::string& w) {
            if (number(e, "ior", w, kNonNegative) && e["ior"].get<double>() != 0.0 && e["ior"].get<double>() < 1.0)
                fail(member(w, "ior"), "expected 0 or a number >= 1, got " + shown(e["ior"].get<double>()));
        });
        extension("KHR_materials_volume", [&](const Json& e, const std::string& w) {
            number(e, "thicknessFactor", w, kNonNegative);
            textureInfo(e, "thicknessTexture", w);
            number(e, "attenuationDistance", w, kPositive);
            numbers(e, "attenuationColor", w, 3, kUnit);
        });
        extension("KHR_materials_specular", [&](const Json& e, const std::string& w) {
            number(e, "specularFactor", w, kUnit);
            textureInfo(e, "specularTexture", w);
            numbers(e, "specularColorFactor", w, 3, kNonNegative);
            textureInfo(e, "specularColorTexture", w);
        });
        extension("KHR_materials_clearcoat", [&](const Json& e, const std::string& w) {
            number(e, "clearcoatFactor", w, kUnit);
            textureInfo(e, "clearcoatTexture", w);
            number(e, "clearcoatRoughnessFactor", w, kUnit);
            textureInfo(e, "clearcoatRoughnessTexture", w);
            textureInfo(e, "clearcoatNormalTexture", w);
        });
        extension("KHR_materials_sheen", [&](const Json& e, const std::string& w) {
            numbers(e, "sheenColorFactor", w, 3, kUnit);
            textureInfo(e, "sheenColorTexture", w);
            number(e, "sheenRoughnessFactor", w, kUnit);
            textureInfo(e, "sheenRoughnessTexture", w);
        });
        extension("KHR_materials_unlit", [](const Json&, const std::string&) {});
    }

    void camera(const Json& camera, const std::string& where) const {
        name(camera, where);
        string(camera, "type", where, true, {"perspective", "orthographic"});
        // glTF 2.0 (5.11): each projection MUST NOT be defined when the other is; a camera with both would
        // be rendered with the one its type names, and the other dropped without a word.
        const std::string type = camera["type"].get<std::string>();
        const char* other = type == "perspective" ? "orthographic" : "perspective";
        if (camera.contains(other))
            fail(member(where, other), "must not be defined when type is \"" + type + "\"");
        if (camera["type"] == "perspective") {
            const Json& p = requiredObject(camera, "perspective", where);
            const std::string at = member(where, "perspective");
            number(p, "aspectRatio", at, kPositive);
            number(p, "yfov", at, kPositive, true);
            number(p, "znear", at, kPositive, true);
            number(p, "zfar", at, kPositive);
            clipRange(p, at);
        } else {
            const Json& o = requiredObject(camera, "orthographic", where);
            const std::string at = member(where, "orthographic");
            number(o, "xmag", at, kAny, true);
            number(o, "ymag", at, kAny, true);
            number(o, "znear", at, kNonNegative, true);
            number(o, "zfar", at, kPositive, true);
            clipRange(o, at);
        }
    }

    // glTF 2.0 (5.12, 5.13): zfar, where given, MUST be greater than znear.
    void clipRange(const Json& projection, const std::string& where) const {
        if (projection.contains("zfar") && projection.contains("znear") &&
            !(projection["zfar"].get<double>() > projection["znear"].get<double>())) {
            fail(member(where, "zfar"), "expected more than znear");
        }
    }

    void animation(const Json& animation, const std::string& where) const {
        name(animation, where);
        eachObject(
            animation, "samplers", where,
            [&](const Json& sampler, const std::string& samplerWhere) {
                index(sampler, "input", samplerWhere, "accessors", "accessor", true);
                index(sampler, "output", samplerWhere, "accessors", "accessor", true);
                string(sampler, "interpolation", samplerWhere, false, {"LINEAR", "STEP", "CUBICSPLINE"});
            },
            true, 1);
        const size_t samplers = animation["samplers"].size();
        eachObject(
            animation, "channels", where,
            [&](const Json& channel, const std::string& channelWhere) {
                checkIndex(*present(channel, "sampler", channelWhere, true), member(channelWhere, "sampler"),
                           samplers, "sampler");
                const Json& target = requiredObject(channel, "target", channelWhere);
                const std::string targetWhere = member(channelWhere, "target");
                index(target, "node", targetWhere, "nodes", "node");
                // The core four, or an extension's (KHR_animation_pointer's "pointer"): the schema allows any
                // string, and channels that do not move nodes are passed over.
                string(target, "path", targetWhere, true);
            },
            true, 1);
    }

    void light(const Json& light, const std::string& where) const {
        name(light, where);
        string(light, "type", where, true, {"directional", "point", "spot"});
        numbers(light, "color", where, 3, kNonNegative);  // [0, 1] in glTF; brighter colours render as written
        number(light, "intensity", where, kNonNegative);
        number(light, "range", where, kPositive);
        if (light["type"] != "spot") return;
        const Json& spot = requiredObject(light, "spot", where);
        const std::string at = member(where, "spot");
        number(spot, "innerConeAngle", at, Range{0.0, kHalfPi, false, true});
        number(spot, "outerConeAngle", at, Range{0.0, kHalfPi, true, false});
    }

    const Json& root_;
    std::string path_;
    size_t lightCount_ = 0;
};

}  // namespace

std::optional<std::string_view> gltfJsonText(std::string_view file, bool binary) {
    if (!binary) return file;
    // GLB: a 12-byte header, then the JSON chunk: its length (little-endian) and type, then the text.
    if (file.size() < 20) return std::nullopt;
    uint32_t length = 0;
    for (int i = 0; i < 4; ++i)
        length |= static_cast<uint32_t>(static_cast<unsigned char>(file[12 + i])) << (8 * i);
    if (file.compare(16, 4, "JSON") != 0 || length > file.size() - 20) return std::nullopt;
    return file.substr(20, length);
}

nlohmann::json readGltfJson(std::string_view file, bool binary) {
    const std::optional<std::string_view> text = gltfJsonText(file, binary);
    if (!text) return Json(Json::value_t::discarded);
    return Json::parse(*text, nullptr, false);
}

std::string glbFile(const std::string& json, const std::string& bin) {
    auto word = [](size_t value) {
        std::string bytes(4, '\0');
        for (int i = 0; i < 4; ++i) bytes[i] = static_cast<char>((value >> (8 * i)) & 0xffu);
        return bytes;
    };
    std::string text = json, data = bin;
    text.resize((text.size() + 3) / 4 * 4, ' ');  // chunks are 4-byte aligned: JSON pads with spaces,
    data.resize((data.size() + 3) / 4 * 4, '\0');  // binary data with zeros
    std::string chunks = word(text.size()) + "JSON" + text;
    if (!data.empty()) chunks += word(data.size()) + std::string("BIN\0", 4) + data;
    return "glTF" + word(2) + word(12 + chunks.size()) + chunks;
}

std::string replaceGlbJson(std::string_view glb, const std::string& json, const std::string& path) {
    auto wordAt = [&](size_t at) {
        uint32_t value = 0;
        for (int i = 0; i < 4; ++i) value |= static_cast<uint32_t>(static_cast<unsigned char>(glb[at + i])) << (8 * i);
        return value;
    };
    const size_t length = glb.size() >= 20 ? wordAt(12) : 0;
    if (glb.size() < 20 || length > glb.size() - 20) throw SceneError(path + ": not a valid GLB file");
    // The binary chunk, when one follows the JSON.
    const size_t binAt = 20 + length;
    std::string bin;
    if (glb.size() >= binAt + 8 && glb.compare(binAt + 4, 4, std::string("BIN\0", 4)) == 0) {
        bin = std::string(glb.substr(binAt + 8, std::min<size_t>(wordAt(binAt), glb.size() - binAt - 8)));
    }
    return glbFile(json, bin);
}

void validateGltfJson(const nlohmann::json& document, const std::string& path) {
    SchemaCheck(document, path).document();
}

}  // namespace vkrt
