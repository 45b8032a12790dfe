// The glTF 2.0 reader (.gltf with data-URI or external buffers, .glb), through Debian's tinygltf, whose
// implementation is compiled here and nowhere else. tinygltf parses the JSON and decodes the buffers; this file
// checks first what tinygltf would trust (the .glb container, which buffers may use the binary chunk, which
// files a buffer may name, no images), and then every index, accessor and buffer view before reading a byte of
// it. The default scene's triangle meshes come out in world space (node transforms applied); normals are the
// file's, or area-weighted from the welded triangles. docs/file-formats.md says what is read.
#include "base/common.h"
#include "io/normals.h"
#include "io/readers.h"
#include "io/text.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>  // tiny_gltf.h uses it without including it
#include <limits>
#include <set>
#include <string_view>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS  // files are read only through the callbacks below
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

namespace ink::io {
namespace {

using Eigen::Matrix3d;
using Eigen::Matrix4d;
using Eigen::Vector3d;
using nlohmann::json;

constexpr uint32_t kGlbMagic = 0x46546C67, kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;

uint32_t le32(const std::string& bytes, size_t at) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap32(v);
    return v;
}

// tinygltf's messages are several lines; the first one, cleaned, says what went wrong.
std::string firstLine(const std::string& text) {
    std::string line = text.substr(0, text.find('\n'));
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '.')) line.pop_back();
    std::string out;
    for (char c : line) out += (c >= 32 && c < 127) ? c : '?';
    return out.size() > 200 ? out.substr(0, 200) + "..." : out;
}

std::string percentDecode(std::string_view s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); };
        if (s[i] == '%' && i + 2 < s.size() + 0 && hex(s[i + 1]) && hex(s[i + 2])) {
            out += char(std::stoi(std::string(s.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// What the file system callbacks may read: files in `dir` (absolute, with every symbolic link resolved), each
// at most once, as many bytes in all as `budget`.
struct Files {
    std::string dir;
    uint64_t budget = kMaxFileBytes;
    std::set<std::string> read;  // the canonical paths read so far
    std::string error;           // the first refusal, reported instead of tinygltf's message
};

// The path with every symbolic link resolved (in the directories on the way too), or "" when that fails.
std::string canonical(const std::string& path) {
    std::error_code ec;
    std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    return ec ? std::string() : p.string();
}

// Whether `path`, resolved, lies in the glTF file's directory (or below it): a buffer that is a symbolic link
// to a file elsewhere, or reached through a linked directory, is outside, whatever its name says.
bool inDir(const std::string& path, const Files& files) {
    std::string real = canonical(path);
    return !files.dir.empty() && real.size() > files.dir.size() + 1 &&
           real.compare(0, files.dir.size(), files.dir) == 0 && real[files.dir.size()] == '/';
}

bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);  // readWholeFile refuses what lies outside, by name
}

std::string expandPath(const std::string& path, void*) { return path; }  // no ~ or $VAR: the path as named

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    Files& files = *static_cast<Files*>(user);
    try {
        if (!inDir(path, files))
            throw Error("'" + path +
                        "' is outside the glTF file's directory once symbolic links are resolved (buffers are read "
                        "only from files in it)");
        // Each file once: one file named by many buffers would be held, and counted, once a buffer.
        std::string real = canonical(path);
        if (!files.read.insert(real).second)
            throw Error("'" + path + "' is named by more than one buffer (each file may be one buffer)");
        std::string bytes = readFileCapped(path, files.budget, "the glTF file's buffers are larger than 2 GiB in all");
        files.budget -= bytes.size();
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (files.error.empty()) files.error = e.what();
        if (err) *err += std::string(e.what()) + "\n";
        return false;
    }
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not supported\n";
    return false;
}

bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;
}

// How deep arrays and objects may nest: glTF itself needs 6 levels; tinygltf (and nlohmann's dump) build and
// write values recursively, so 20,000 levels in an ignored `extras` overflowed the stack.
constexpr size_t kMaxJsonDepth = 64;
// The most objects tinygltf may build (nodes, meshes, primitives, accessors, buffer views, buffers, scenes):
// each costs it some 350-460 bytes, from as little as 3 bytes of JSON (`{},`). 500,000 is about 230 MB.
constexpr size_t kMaxGltfObjects = 500000;
// Index, count, offset and size members: tinygltf stores indices as int and would cast 2^32 to 0, a negative
// offset it leaves at 0. Each must be an integer 0..2^31-1 (no glTF Inkwell reads has a larger one).
constexpr uint64_t kMaxGltfInteger = (uint64_t(1) << 31) - 1;

// Refuses JSON nested deeper than kMaxJsonDepth before anything parses it (the check counts brackets outside
// strings; anything malformed is left to the parser).
void checkDepth(std::string_view text, const std::string& name) {
    size_t depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                fail(name, "glTF JSON: arrays and objects nest more than " + std::to_string(kMaxJsonDepth) +
                               " levels deep (at byte " + std::to_string(i) + ")");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
}

bool isIndexKey(std::string_view key) {
    static constexpr std::string_view kKeys[] = {"bufferView",    "buffer",
                                                 "indices",       "material",
                                                 "mesh",          "skin",
                                                 "camera",        "source",
                                                 "sampler",       "node",
                                                 "scene",         "input",
                                                 "output",        "index",
                                                 "texCoord",      "skeleton",
                                                 "children",      "nodes",
                                                 "joints",        "count",
                                                 "byteOffset",    "mode",
                                                 "byteLength",    "byteStride",
                                                 "componentType", "inverseBindMatrices"};
    return std::find(std::begin(kKeys), std::end(kKeys), key) != std::end(kKeys);
}

// The top-level array an index member names, or "" (a count, an offset, a sampler of either kind).
std::string_view referenceOf(std::string_view key) {
    static constexpr std::pair<std::string_view, std::string_view> kTargets[] = {{"bufferView", "bufferViews"},
                                                                                 {"buffer", "buffers"},
                                                                                 {"indices", "accessors"},
                                                                                 {"material", "materials"},
                                                                                 {"mesh", "meshes"},
                                                                                 {"skin", "skins"},
                                                                                 {"camera", "cameras"},
                                                                                 {"source", "images"},
                                                                                 {"node", "nodes"},
                                                                                 {"scene", "scenes"},
                                                                                 {"input", "accessors"},
                                                                                 {"output", "accessors"},
                                                                                 {"index", "textures"},
                                                                                 {"skeleton", "nodes"},
                                                                                 {"children", "nodes"},
                                                                                 {"nodes", "nodes"},
                                                                                 {"joints", "nodes"},
                                                                                 {"inverseBindMatrices", "accessors"}};
    for (const auto& [k, target] : kTargets)
        if (k == key) return target;
    return {};
}

// How many objects each top-level array of the file holds (before anything is dropped).
using Counts = std::vector<std::pair<std::string, size_t>>;

// Every index, count, offset and size, at any depth: an integer 0..kMaxGltfInteger; an index must also name an
// object the file has (a material, a camera or an image too, though they are not read). `at` spells where;
// `index` says that a number here is one, `target` the array it indexes, `members` that an object's members
// are indices (`attributes`, morph `targets`).
void checkIntegers(const json& value, const std::string& at, bool index, std::string_view target, bool members,
                   const Counts& counts, const std::string& name) {
    if (value.is_number()) {
        if (!index) return;
        if (!(value.is_number_unsigned() && value.get<uint64_t>() <= kMaxGltfInteger))
            fail(name, "glTF: " + firstLine(at) + " is " + firstLine(value.dump()) +
                           ", not an index, count or size (an integer 0 to " + std::to_string(kMaxGltfInteger) + ")");
        if (target.empty()) return;
        size_t have = 0;
        for (const auto& [array, n] : counts)
            if (array == target) have = n;
        if (value.get<uint64_t>() >= have)
            fail(name, "glTF: " + firstLine(at) + " is " + std::to_string(value.get<uint64_t>()) +
                           ", but the file has " + std::to_string(have) + " " + std::string(target));
    } else if (value.is_array()) {
        for (size_t i = 0; i < value.size(); ++i)
            checkIntegers(value[i], at + "[" + std::to_string(i) + "]", index, target, members, counts, name);
    } else if (value.is_object()) {
        for (auto it = value.begin(); it != value.end(); ++it) {
            bool isIndex = members || isIndexKey(it.key());
            std::string_view to = members ? std::string_view("accessors") : referenceOf(it.key());
            checkIntegers(it.value(), at.empty() ? it.key() : at + "." + it.key(), isIndex, to,
                          it.key() == "attributes" || it.key() == "targets", counts, name);
        }
    }
}

// Drops every `extras` and `extensions` member (nothing Inkwell reads is in them; tinygltf would build
// values of them at some 150 bytes a JSON value).
void dropExtras(json& value) {
    if (value.is_object()) {
        value.erase("extras");
        value.erase("extensions");
        for (auto& member : value.items()) dropExtras(member.value());
    } else if (value.is_array()) {
        for (json& element : value) dropExtras(element);
    }
}

// Checks the JSON before tinygltf acts on it, and drops what is not needed (images: tinygltf would hand an
// image's buffer view to the image loader unchecked; materials, animations and the rest cost it memory far
// beyond their bytes). Returns the JSON to give tinygltf.
std::string vetJson(std::string_view text, const std::string& name, bool binary, uint64_t binSize, bool external) {
    checkDepth(text, name);
    json doc;
    try {
        doc = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        fail(name, "glTF JSON: " + firstLine(e.what()));
    }
    if (!doc.is_object()) fail(name, "glTF JSON: the top level is not an object");
    auto asset = doc.find("asset");
    if (asset == doc.end() || !asset->is_object()) fail(name, "glTF: no 'asset' object");
    auto version = asset->find("version");
    if (version != asset->end() && version->is_number())  // glTF 1.0's exporters wrote it as a number
        fail(name, "glTF: asset version " + version->dump() + " (glTF 1.0); this reader reads glTF 2.0");
    if (version == asset->end() || !version->is_string())
        fail(name, "glTF: no asset version (this reader reads glTF 2.0)");
    std::string v = version->get<std::string>();
    if (v.substr(0, 2) != "2.") fail(name, "glTF: asset version " + ink::quoted(v) + "; this reader reads glTF 2.0");
    if (auto required = doc.find("extensionsRequired"); required != doc.end() && required->is_array())
        for (const json& e : *required)
            if (e.is_string())
                fail(name,
                     "glTF: requires the extension " + ink::quoted(e.get<std::string>()) + ", which is not supported");
    if (auto buffers = doc.find("buffers"); buffers != doc.end()) {
        if (!buffers->is_array()) fail(name, "glTF: 'buffers' is not an array");
        for (size_t i = 0; i < buffers->size(); ++i) {
            const json& b = (*buffers)[i];
            std::string at = "glTF buffer " + std::to_string(i);
            if (!b.is_object()) fail(name, at + ": not an object");
            auto length = b.find("byteLength");
            if (length == b.end() || !length->is_number_unsigned() || length->get<uint64_t>() == 0)
                fail(name, at + ": 'byteLength' is not a positive integer");
            uint64_t bytes = length->get<uint64_t>();
            auto uri = b.find("uri");
            if (uri == b.end()) {
                // Only buffer 0 of a .glb is its binary chunk; a file that points more at it is not glTF.
                if (!binary) fail(name, at + ": no 'uri'");
                if (i != 0) fail(name, at + ": no 'uri' (only buffer 0 of a .glb is its binary chunk)");
                if (bytes > binSize)
                    fail(name, at + ": 'byteLength' " + std::to_string(bytes) + " is larger than the binary chunk (" +
                                   std::to_string(binSize) + " bytes)");
                continue;
            }
            if (!uri->is_string()) fail(name, at + ": 'uri' is not a string");
            std::string u = uri->get<std::string>();
            if (u.rfind("data:", 0) == 0) continue;  // decoded by tinygltf, which checks its length
            std::string path = percentDecode(u);
            bool scheme = path.find(':') != std::string::npos;
            bool escapes = path.empty() || path[0] == '/' || path.find('\\') != std::string::npos ||
                           path.find('\0') != std::string::npos;
            for (size_t start = 0; start <= path.size() && !escapes;) {
                size_t end = std::min(path.find('/', start), path.size());
                if (path.substr(start, end - start) == "..") escapes = true;
                start = end + 1;
            }
            if (scheme || escapes)
                fail(name, at + ": 'uri' " + ink::quoted(u) +
                               " is not a file in the glTF file's directory (URLs, absolute paths and '..' are "
                               "refused)");
            if (!external) fail(name, at + ": external buffer " + ink::quoted(u) + " is not read here");
        }
    }
    // Every index must name an object the file has, also in the sections dropped below: counted first.
    Counts counts;
    for (auto it = doc.begin(); it != doc.end(); ++it)
        if (it.value().is_array()) counts.emplace_back(it.key(), it.value().size());
    // What tinygltf needs to find the meshes; the rest is dropped before it builds objects of it.
    static constexpr std::string_view kKept[] = {"asset",     "scene",       "scenes",  "nodes",         "meshes",
                                                 "accessors", "bufferViews", "buffers", "extensionsUsed"};
    for (auto it = doc.begin(); it != doc.end();) {
        bool keep = std::find(std::begin(kKept), std::end(kKept), it.key()) != std::end(kKept);
        it = keep ? std::next(it) : doc.erase(it);
    }
    dropExtras(doc);
    size_t objects = 0;
    for (const char* key : {"scenes", "nodes", "meshes", "accessors", "bufferViews", "buffers"}) {
        auto list = doc.find(key);
        if (list == doc.end()) continue;
        if (!list->is_array()) fail(name, std::string("glTF: '") + key + "' is not an array");
        objects += list->size();
        if (std::string_view(key) == "meshes")
            for (const json& mesh : *list)
                if (auto primitives = mesh.find("primitives"); mesh.is_object() && primitives != mesh.end())
                    objects += primitives->size();
    }
    if (objects > kMaxGltfObjects)
        fail(name, "glTF: " + std::to_string(objects) +
                       " scenes, nodes, meshes, primitives, accessors, buffer views "
                       "and buffers; the limit is " +
                       std::to_string(kMaxGltfObjects));
    checkIntegers(doc, "", false, {}, false, counts, name);
    return doc.dump();
}

// The size in bytes of one component.
size_t componentSize(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

double component(const unsigned char* p, int type, bool normalized) {
    auto get = [p](auto v) {
        std::memcpy(&v, p, sizeof v);
        return v;
    };
    // glTF is little-endian throughout.
    if constexpr (std::endian::native == std::endian::big) return 0;  // not built there
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return normalized ? std::max(get(int8_t()) / 127.0, -1.0) : get(int8_t());
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return normalized ? get(uint8_t()) / 255.0 : get(uint8_t());
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return normalized ? std::max(get(int16_t()) / 32767.0, -1.0) : get(int16_t());
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return normalized ? get(uint16_t()) / 65535.0 : get(uint16_t());
        case TINYGLTF_COMPONENT_TYPE_INT:
            return get(int32_t());
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return get(uint32_t());
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return get(float());
    }
    return 0;
}

// One accessor, checked against its buffer view and the view against its buffer before anything is read.
struct View {
    const unsigned char* data = nullptr;
    uint64_t count = 0, stride = 0;
    int componentType = 0, components = 0;
    bool normalized = false;

    double get(uint64_t i, int k) const {
        return component(data + i * stride + uint64_t(k) * componentSize(componentType), componentType, normalized);
    }
};

View accessorView(const tinygltf::Model& model, int index, int components, const char* what, const std::string& name) {
    std::string at = std::string("glTF ") + what + " accessor " + std::to_string(index);
    if (index < 0 || size_t(index) >= model.accessors.size())
        fail(name, at + ": there is no such accessor (the file has " + std::to_string(model.accessors.size()) + ")");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    if (a.sparse.isSparse) fail(name, at + ": sparse accessors are not supported");
    if (a.bufferView < 0) fail(name, at + ": has no buffer view");
    int have = a.type == TINYGLTF_TYPE_SCALAR ? 1 : a.type == TINYGLTF_TYPE_VEC3 ? 3 : -1;
    if (have != components)
        fail(name, at + ": type is not " + (components == 1 ? "SCALAR" : "VEC3") + " (glTF type code " +
                       std::to_string(a.type) + ")");
    size_t size = componentSize(a.componentType);
    if (size == 0) fail(name, at + ": component type " + std::to_string(a.componentType) + " is not supported");
    if (a.count > kMaxElements)
        fail(name,
             at + ": claims " + std::to_string(a.count) + " elements; the limit is " + std::to_string(kMaxElements));
    if (size_t(a.bufferView) >= model.bufferViews.size())
        fail(name, at + ": buffer view " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
        fail(name, at + ": buffer view " + std::to_string(a.bufferView) + " names buffer " + std::to_string(bv.buffer) +
                       ", which does not exist");
    const tinygltf::Buffer& buffer = model.buffers[size_t(bv.buffer)];
    uint64_t bufferSize = buffer.data.size();
    // Sizes from the file are at most 2^64 - 1 each; keep every sum below overflow.
    constexpr uint64_t kHuge = uint64_t(1) << 60;
    if (bv.byteOffset > kHuge || bv.byteLength > kHuge || bv.byteOffset + bv.byteLength > bufferSize)
        fail(name, "glTF buffer view " + std::to_string(a.bufferView) + ": bytes " + std::to_string(bv.byteOffset) +
                       " + " + std::to_string(bv.byteLength) + " lie outside buffer " + std::to_string(bv.buffer) +
                       " (" + std::to_string(bufferSize) + " bytes)");
    uint64_t element = size * uint64_t(components);
    uint64_t stride = bv.byteStride ? bv.byteStride : element;
    if (stride < element)
        fail(name, at + ": the buffer view's stride " + std::to_string(stride) + " is less than an element (" +
                       std::to_string(element) + " bytes)");
    if (a.byteOffset % size != 0 || (bv.byteOffset + a.byteOffset) % size != 0)
        fail(name, at + ": byte offset " + std::to_string(a.byteOffset) + " is not aligned to its components");
    View view;
    view.count = a.count;
    view.stride = stride;
    view.componentType = a.componentType;
    view.components = components;
    view.normalized = a.normalized;
    if (a.count == 0) return view;
    if (a.byteOffset > kHuge || a.byteOffset + (a.count - 1) * stride + element > bv.byteLength)
        fail(name, at + ": " + std::to_string(a.count) + " elements of " + std::to_string(element) + " bytes, every " +
                       std::to_string(stride) + " from byte " + std::to_string(a.byteOffset) +
                       ", run past the end of buffer view " + std::to_string(a.bufferView) + " (" +
                       std::to_string(bv.byteLength) + " bytes)");
    view.data = buffer.data.data() + bv.byteOffset + a.byteOffset;
    return view;
}

Matrix4d nodeMatrix(const tinygltf::Node& node) {
    Matrix4d m = Matrix4d::Identity();
    if (node.matrix.size() == 16) {
        for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = node.matrix[size_t(k)];  // column-major
        return m;
    }
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    if (node.translation.size() == 3)
        t.translate(Vector3d(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
        Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        if (q.norm() > 0) t.rotate(q.normalized().toRotationMatrix());
    }
    if (node.scale.size() == 3) t.scale(Vector3d(node.scale[0], node.scale[1], node.scale[2]));
    return t.matrix();
}

// What the scene gives: points with the file's normals, and a triangle soup (world space) for the rest.
struct Gathered {
    OrientedPoints given;
    std::vector<Vector3d> corners;  // three a triangle
    uint64_t instanced = 0, limit = 0;
    size_t skippedPrimitives = 0, singularNodes = 0;
};

void addMesh(const tinygltf::Model& model, int meshIndex, const Matrix4d& world, Gathered& out,
             const std::string& name) {
    if (meshIndex < 0 || size_t(meshIndex) >= model.meshes.size())
        fail(name, "glTF: mesh " + std::to_string(meshIndex) + " does not exist (the file has " +
                       std::to_string(model.meshes.size()) + ")");
    Matrix3d linear = world.topLeftCorner<3, 3>();
    double det = linear.determinant();
    if (!world.allFinite() || !std::isfinite(det) || det == 0) {
        ++out.singularNodes;
        return;
    }
    Matrix3d normalMatrix = linear.inverse().transpose();
    const tinygltf::Mesh& mesh = model.meshes[size_t(meshIndex)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = mesh.primitives[p];
        std::string at = "glTF mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
        auto position = prim.attributes.find("POSITION");
        auto normal = prim.attributes.find("NORMAL");
        bool triangles = prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
                         prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
        bool points = prim.mode == TINYGLTF_MODE_POINTS && normal != prim.attributes.end();
        if ((!triangles && !points) || position == prim.attributes.end()) {
            ++out.skippedPrimitives;
            continue;
        }
        View pos = accessorView(model, position->second, 3, "POSITION", name);
        View nrm;
        if (normal != prim.attributes.end()) {
            nrm = accessorView(model, normal->second, 3, "NORMAL", name);
            if (nrm.count != pos.count)
                fail(name, at + ": " + std::to_string(nrm.count) + " normals for " + std::to_string(pos.count) +
                               " positions");
        }
        out.instanced += pos.count;
        if (out.instanced > out.limit)
            fail(name, "glTF: the scene instances more than " + std::to_string(out.limit) +
                           " vertices and indices (the limit is 100 million, and 64 a byte of the file and its "
                           "buffers)");
        auto world3 = [&](uint64_t i) {
            Vector3d v(pos.get(i, 0), pos.get(i, 1), pos.get(i, 2));
            if (!v.allFinite())
                fail(name, at + ": vertex " + std::to_string(i) + ": coordinate is not finite " + str(v));
            return Vector3d((world * v.homogeneous()).head<3>());
        };
        // Corner indices, checked.
        std::vector<uint64_t> corners;
        if (triangles) {
            if (prim.indices >= 0) {
                View idx = accessorView(model, prim.indices, 1, "indices", name);
                if (idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                    idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                    idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                    fail(name, at + ": indices are not of an unsigned integer type");
                idx.normalized = false;
                // Indices cost memory as vertices do: a small file whose primitives all use one large index
                // accessor would make every instance read it again.
                out.instanced += idx.count;
                if (out.instanced > out.limit)
                    fail(name, "glTF: the scene instances more than " + std::to_string(out.limit) +
                                   " vertices and indices (the limit is 100 million, and 64 a byte of the file and "
                                   "its buffers)");
                corners.resize(idx.count);
                for (uint64_t i = 0; i < idx.count; ++i) {
                    double c = idx.get(i, 0);
                    if (c >= double(pos.count))
                        fail(name, at + ": index " + num(c) + " is out of range (the primitive has " +
                                       std::to_string(pos.count) + " vertices)");
                    corners[i] = uint64_t(c);
                }
            } else {
                corners.resize(pos.count);
                for (uint64_t i = 0; i < pos.count; ++i) corners[i] = i;
            }
            if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
                // As a list: strip triangle i is (i, i+1, i+2), every other one turned round; fan triangle i is
                // (i+1, i+2, 0).
                std::vector<uint64_t> list;
                for (size_t i = 0; i + 2 < corners.size(); ++i) {
                    bool strip = prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP;
                    uint64_t a = strip ? corners[i] : corners[i + 1],
                             b = strip ? corners[i + 1 + i % 2] : corners[i + 2],
                             c = strip ? corners[i + 2 - i % 2] : corners[0];
                    list.insert(list.end(), {a, b, c});
                }
                corners = std::move(list);
            } else if (corners.size() % 3 != 0) {
                fail(name, at + ": " + std::to_string(corners.size()) + " corners is not a whole number of triangles");
            }
        }
        // A mirroring transform turns the winding around (the glTF specification says so too).
        bool flip = det < 0;
        if (nrm.count > 0) {
            // The file's normals, for every vertex of the primitive, and its triangles in their numbering.
            const uint64_t first = out.given.positions.size();
            for (size_t c = 0; c + 2 < corners.size(); c += 3)
                out.given.triangles.push_back({uint32_t(first + corners[c]),
                                               uint32_t(first + corners[flip ? c + 2 : c + 1]),
                                               uint32_t(first + corners[flip ? c + 1 : c + 2])});
            for (uint64_t i = 0; i < pos.count; ++i) {
                Vector3d n(nrm.get(i, 0), nrm.get(i, 1), nrm.get(i, 2));
                if (!n.allFinite())
                    fail(name, at + ": vertex " + std::to_string(i) + ": normal is not finite " + str(n));
                out.given.positions.push_back(world3(i));
                out.given.normals.push_back(safeNormalized(normalMatrix * n));  // a scaled node keeps it unit
            }
            continue;
        }
        for (size_t c = 0; c + 2 < corners.size(); c += 3) {
            out.corners.push_back(world3(corners[c]));
            out.corners.push_back(world3(corners[flip ? c + 2 : c + 1]));
            out.corners.push_back(world3(corners[flip ? c + 1 : c + 2]));
        }
    }
}

}  // namespace

OrientedPoints parseGltf(const std::string& bytes, const std::string& name, bool binary, bool externalFiles) {
    // A .gltf that holds a .glb (some tools write one under the other's name) is read as what it is.
    if (bytes.size() >= 4 && le32(bytes, 0) == kGlbMagic) binary = true;
    std::string_view jsonText(bytes);
    std::string_view bin;
    if (binary) {
        if (bytes.size() < 20 || le32(bytes, 0) != kGlbMagic)
            fail(name, "not a binary glTF file (no 'glTF' magic and 20-byte header)");
        if (le32(bytes, 4) != 2)
            fail(name, "binary glTF version " + std::to_string(le32(bytes, 4)) + "; this reader reads 2");
        uint64_t length = le32(bytes, 8);
        if (length != bytes.size())
            fail(name, "binary glTF header says " + std::to_string(length) + " bytes, the file has " +
                           std::to_string(bytes.size()) + " (truncated?)");
        uint64_t jsonLength = le32(bytes, 12);
        if (le32(bytes, 16) != kChunkJson) fail(name, "binary glTF: the first chunk is not JSON");
        if (20 + jsonLength > length)
            fail(name, "binary glTF: the JSON chunk (" + std::to_string(jsonLength) +
                           " bytes) runs past the end of the file");
        jsonText = std::string_view(bytes).substr(20, jsonLength);
        uint64_t next = (20 + jsonLength + 3) / 4 * 4;
        if (next + 8 <= length) {
            uint64_t binLength = le32(bytes, next);
            if (le32(bytes, next + 4) == kChunkBin) {
                if (next + 8 + binLength > length)
                    fail(name, "binary glTF: the BIN chunk (" + std::to_string(binLength) +
                                   " bytes) runs past the end of the file");
                bin = std::string_view(bytes).substr(next + 8, binLength);
            }
        }
    } else {
        rejectBinary(bytes, name);
    }
    std::string cleanJson = vetJson(jsonText, name, binary, bin.size(), externalFiles);

    Files files;
    if (externalFiles) {
        // The directory the file is in, every link resolved, as the buffers' paths will be: a buffer must
        // resolve to a file inside it.
        std::error_code ec;
        std::filesystem::path dir = std::filesystem::absolute(name, ec).parent_path();
        if (!ec) files.dir = canonical(dir.string());
        while (files.dir.size() > 1 && files.dir.back() == '/') files.dir.pop_back();
    }
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({fileExists, expandPath, readWholeFile, writeWholeFile, &files});
    loader.SetImageLoader(ignoreImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok;
    if (binary) {
        // The same container around the checked JSON, padded to 4 bytes as the format wants.
        while (cleanJson.size() % 4) cleanJson += ' ';
        std::string glb(20, '\0');
        auto put = [&glb](size_t at, uint64_t v) {
            for (int k = 0; k < 4; ++k) glb[at + size_t(k)] = char((v >> (8 * k)) & 0xff);
        };
        glb += cleanJson;
        if (!bin.empty()) {
            size_t at = glb.size();
            glb.append(8, '\0');
            put(at, bin.size());
            put(at + 4, kChunkBin);
            glb.append(bin);
            while (glb.size() % 4) glb += '\0';
        }
        if (glb.size() > std::numeric_limits<uint32_t>::max()) fail(name, "binary glTF: larger than 4 GiB");
        put(0, kGlbMagic);
        put(4, 2);
        put(8, glb.size());
        put(12, cleanJson.size());
        put(16, kChunkJson);
        ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                         unsigned(glb.size()), files.dir);
    } else {
        ok = loader.LoadASCIIFromString(&model, &err, &warn, cleanJson.data(), unsigned(cleanJson.size()), files.dir);
    }
    if (!files.error.empty()) fail(name, "glTF buffer: " + files.error);
    if (!ok) fail(name, "glTF: " + (err.empty() ? std::string("tinygltf could not read it") : firstLine(err)));

    // The default scene's root nodes; without one, every scene's; without scenes, every node no node has as
    // a child. Each node may have one parent (the nodes form trees), which also rules out cycles.
    size_t n = model.nodes.size();
    std::vector<int> parent(n, -1);
    for (size_t i = 0; i < n; ++i)
        for (int c : model.nodes[i].children) {
            if (c < 0 || size_t(c) >= n)
                fail(name, "glTF node " + std::to_string(i) + ": child " + std::to_string(c) + " does not exist");
            if (parent[size_t(c)] >= 0 || size_t(c) == i)
                fail(name, "glTF node " + std::to_string(c) + " has more than one parent (nodes must form trees)");
            parent[size_t(c)] = int(i);
        }
    std::vector<int> roots;
    auto addScene = [&](const tinygltf::Scene& scene) {
        for (int r : scene.nodes) {
            if (r < 0 || size_t(r) >= n) fail(name, "glTF scene: node " + std::to_string(r) + " does not exist");
            roots.push_back(r);
        }
    };
    if (model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size())
        addScene(model.scenes[size_t(model.defaultScene)]);
    else if (model.defaultScene >= 0)
        fail(name, "glTF: the default scene " + std::to_string(model.defaultScene) + " does not exist");
    else if (!model.scenes.empty())
        for (const tinygltf::Scene& s : model.scenes) addScene(s);
    else
        for (size_t i = 0; i < n; ++i)
            if (parent[i] < 0) roots.push_back(int(i));

    Gathered out;
    uint64_t fileBytes = bytes.size() + (kMaxFileBytes - files.budget);
    out.limit = std::min<uint64_t>(kMaxElements, 64 * fileBytes);
    // Depth-first over the trees; a root that is also a child elsewhere, or listed twice, would be visited
    // twice, which is allowed (it is instancing) but bounded by the vertex limit.
    std::vector<std::pair<int, Matrix4d>> stack;
    for (int r : roots) stack.emplace_back(r, Matrix4d::Identity());
    size_t visited = 0;
    while (!stack.empty()) {
        auto [index, above] = stack.back();
        stack.pop_back();
        if (++visited > n * 4 + 16)
            fail(name, "glTF: the node hierarchy has a cycle, or the scenes list nodes repeatedly");
        const tinygltf::Node& node = model.nodes[size_t(index)];
        Matrix4d world = above * nodeMatrix(node);
        if (node.mesh >= 0) addMesh(model, node.mesh, world, out, name);
        for (int c : node.children) stack.emplace_back(c, world);
    }
    if (n == 0)
        for (size_t m = 0; m < model.meshes.size(); ++m) addMesh(model, int(m), Matrix4d::Identity(), out, name);

    if (out.skippedPrimitives > 0)
        note(name + ": skipped " + std::to_string(out.skippedPrimitives) +
             " glTF primitive(s) that are lines, points without normals, or have no POSITION");
    if (out.singularNodes > 0)
        note(name + ": skipped " + std::to_string(out.singularNodes) +
             " mesh instance(s) whose node transform is singular or not finite");

    OrientedPoints points = std::move(out.given);
    replaceZeroNormals(points, name);
    if (!out.corners.empty()) {
        std::vector<Vector3d> vertices;
        Polygons triangles;
        triangles.indices = weld(out.corners, vertices);
        triangles.sizes.assign(out.corners.size() / 3, 3);
        std::vector<size_t> kept;
        size_t degenerate = 0;
        OrientedPoints computed = areaNormalPoints(vertices, triangles, kept, degenerate);
        if (degenerate > 0)
            note(name + ": dropped " + std::to_string(degenerate) + " vertex" + (degenerate == 1 ? "" : "es") +
                 " whose triangles all have zero area");
        const uint32_t first = uint32_t(points.positions.size());
        for (const Triangle& t : computed.triangles)
            points.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
        points.positions.insert(points.positions.end(), computed.positions.begin(), computed.positions.end());
        points.normals.insert(points.normals.end(), computed.normals.begin(), computed.normals.end());
    }
    if (points.positions.empty())
        fail(name, "glTF: the scene has no triangles (or points with normals) to read" +
                       (out.skippedPrimitives ? " (" + std::to_string(out.skippedPrimitives) +
                                                    " primitive(s) of lines, or points without normals, skipped)"
                                              : std::string()));
    finish(points, name, [](size_t i) { return "glTF vertex " + std::to_string(i) + " (in scene order)"; });
    return points;
}

}  // namespace ink::io
