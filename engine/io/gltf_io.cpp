#include "engine/io/gltf_io.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <nlohmann/json.hpp>
#include <numbers>
#include <span>
#include <string>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "engine/io/text_input.h"
#include "engine/io/texture_io.h"
#include "engine/scene/affine3.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// Images are decoded later, and only those a material's base colour uses (texture_io.h). Here the
// bytes of an image given by a data URI are kept as they are; an image in a file is read again by
// the reader (to name the reason when it cannot be), one in a buffer view from its buffer, within
// the view's checked bounds (tinygltf hands over a pointer into the buffer without checking them,
// so the bytes given for such an image are not touched).
bool keepImageBytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                    const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && image->uri.empty() && bytes != nullptr && size > 0) {
        image->image.assign(bytes, bytes + size);
        image->as_is = true;
    }
    return true;
}

// A URI's %XX escapes decoded (RFC 3986), as tinygltf reads a file's name; a malformed escape is
// left as it is.
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        const auto hex = [](char c) {
            return c >= '0' && c <= '9'   ? c - '0'
                   : c >= 'a' && c <= 'f' ? c - 'a' + 10
                   : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                          : -1;
        };
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// File access for the buffers and images a glTF names by URI, in place of tinygltf's own. Its
// reader sizes a file by seeking to the end, which on a directory (a URI of "." or "/", found by
// fuzzing) reports 2^63 - 1 bytes and asks for that much memory; it also accepts devices and
// pipes. Here only a regular file of bounded size is read, and the reason for a refusal is named.
constexpr uintmax_t kMaxExternalBytes = 0x7fffffffu;

bool pathExists(const std::string& path, void*) {
    std::error_code ec;
    return fs::exists(path, ec);
}

std::string samePath(const std::string& path, void*) { return path; }

bool readRegularFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void*) {
    const auto refuse = [&](const std::string& why) {
        if (err) *err += why;
        return false;
    };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return refuse("not a regular file");
    const uintmax_t size = fs::file_size(path, ec);
    if (ec) return refuse("cannot read its size (" + ec.message() + ")");
    if (size == 0) return refuse("empty file");
    if (size > kMaxExternalBytes) return refuse("larger than 2 GiB");
    try {
        *out = readWholeFileBytes(path);
    } catch (const FileReadError& e) {
        return refuse(cannotReadFile(e.reason));
    }
    return true;
}

bool refuseWrite(std::string* err, const std::string& path, const std::vector<unsigned char>&,
                 void*) {
    if (err) *err += path + ": the glTF loader writes no files\n";
    return false;
}

// ---- what tinygltf does not check: the version and the required extensions --------------------

// Required extensions the loader reads (KHR_materials_emissive_strength, KHR_texture_transform) or
// whose absence it handles (an image only in a format of the other texture extensions cannot be
// decoded: its material keeps its colour factor, with a warning).
constexpr std::string_view kSupportedRequiredExtensions[] = {"KHR_materials_emissive_strength",
                                                             "KHR_texture_transform",
                                                             "KHR_texture_basisu",
                                                             "EXT_texture_webp",
                                                             "EXT_texture_avif",
                                                             "MSFT_texture_dds"};
constexpr const char* kDraco = "KHR_draco_mesh_compression";

std::string supportedExtensionList() {
    std::string list;
    for (std::string_view e : kSupportedRequiredExtensions)
        list += std::string(list.empty() ? "" : ", ") + std::string(e);
    return list;
}

// Refuses, before tinygltf parses the file, what it would misreport: glTF 1.0 (an "asset" object
// not found, "no faces"), Draco-compressed meshes ("accessor[0] invalid bufferView") and other
// required extensions it would silently ignore. Text that is no JSON, or a GLB without a JSON
// chunk, is left for tinygltf to report.
void checkVersionAndExtensions(const std::string& data, bool binary, const std::string& file) {
    const auto refuse = [&](const std::string& why) { throw makeSceneError(file, 0, why); };
    const std::string kOnly2 = "; only glTF 2.0 is (re-export or convert the file to glTF 2.0)";
    std::string_view text = data;
    if (binary) {
        if (data.size() < 12) return;
        uint32_t version = 0;
        std::memcpy(&version, data.data() + 4, 4);
        if (version == 1)
            refuse("GLB: binary glTF 1.0 (GLB version 1, KHR_binary_glTF) is not supported" +
                   kOnly2);
        if (version != 2) return;  // tinygltf names it
        uint32_t length = 0, type = 0;
        if (data.size() < 20) return;
        std::memcpy(&length, data.data() + 12, 4);
        std::memcpy(&type, data.data() + 16, 4);
        if (type != 0x4E4F534Au || length > data.size() - 20) return;  // "JSON"
        text = std::string_view(data).substr(20, length);
    }
    using Json = nlohmann::json;
    const Json root = Json::parse(text.begin(), text.end(), nullptr, false);
    if (root.is_discarded() || !root.is_object()) return;
    const auto member = [](const Json& j, const char* key) -> const Json* {
        if (!j.is_object()) return nullptr;
        const auto it = j.find(key);
        return it == j.end() ? nullptr : &*it;
    };

    // The version: asset.version's major number, else the shape of the top-level collections
    // (dictionaries keyed by id in glTF 1.0, arrays in 2.0).
    const Json* asset = member(root, "asset");
    const Json* version = asset ? member(*asset, "version") : nullptr;
    if (version && version->is_string()) {
        const std::string v = version->get<std::string>();
        const std::string major = v.substr(0, v.find('.'));
        if (major == "1")
            refuse("glTF 1.0 is not supported (asset.version \"" + v + "\")" + kOnly2);
        if (major != "2")
            refuse("glTF version \"" + v.substr(0, 20) + "\" is not supported" + kOnly2);
    } else {
        for (const char* key :
             {"meshes", "accessors", "bufferViews", "buffers", "nodes", "materials", "scenes"}) {
            const Json* collection = member(root, key);
            if (collection && collection->is_object())
                refuse(std::string("glTF 1.0 is not supported (\"") + key +
                       "\" is a dictionary, as in glTF 1.0, and there is no asset.version)" +
                       kOnly2);
        }
    }

    if (const Json* required = member(root, "extensionsRequired");
        required && required->is_array()) {
        for (const Json& e : *required) {
            if (!e.is_string()) continue;
            const std::string name = e.get<std::string>();
            if (name == kDraco)
                refuse(
                    "required extension KHR_draco_mesh_compression: Draco-compressed meshes are "
                    "not supported (export the file without Draco compression)");
            if (std::find(std::begin(kSupportedRequiredExtensions),
                          std::end(kSupportedRequiredExtensions),
                          name) == std::end(kSupportedRequiredExtensions))
                refuse("required extension \"" + name.substr(0, 80) +
                       "\" is not supported (supported: " + supportedExtensionList() + ")");
        }
    }

    // Draco on a primitive without the extension required: loadable only where the primitive
    // keeps its uncompressed data (a POSITION accessor with a buffer view), as the extension's
    // fallback.
    const Json* meshes = member(root, "meshes");
    const Json* accessors = member(root, "accessors");
    if (!meshes || !meshes->is_array()) return;
    for (size_t m = 0; m < meshes->size(); ++m) {
        const Json* primitives = member((*meshes)[m], "primitives");
        if (!primitives || !primitives->is_array()) continue;
        for (size_t p = 0; p < primitives->size(); ++p) {
            const Json& prim = (*primitives)[p];
            const Json* extensions = member(prim, "extensions");
            if (!extensions || !member(*extensions, kDraco)) continue;
            const Json* attributes = member(prim, "attributes");
            const Json* position = attributes ? member(*attributes, "POSITION") : nullptr;
            bool fallback = false;
            if (position && position->is_number_unsigned() && accessors && accessors->is_array()) {
                const auto a = position->get<uint64_t>();
                fallback = a < accessors->size() && member((*accessors)[a], "bufferView");
            }
            if (!fallback)
                refuse("mesh " + std::to_string(m) + " primitive " + std::to_string(p) +
                       ": compressed with KHR_draco_mesh_compression (Draco), which is not "
                       "supported, and without uncompressed data (export the file without Draco "
                       "compression)");
        }
    }
}

// Where a face came from, for messages.
struct PrimitiveRange {
    uint32_t firstFace;
    int node, mesh, primitive;
};

class GltfReader {
  public:
    GltfReader(const tinygltf::Model& model, std::string file, fs::path directory, bool strict,
               Scene& scene)
        : model_(model),
          file_(std::move(file)),
          directory_(std::move(directory)),
          strict_(strict),
          scene_(scene) {}

    void read() {
        readMaterials();
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (s >= static_cast<int>(model_.scenes.size()))
                fail("scene " + std::to_string(s) + " does not exist");
            roots = model_.scenes[static_cast<size_t>(s)].nodes;
        } else {
            std::vector<bool> isChild(model_.nodes.size(), false);
            for (const tinygltf::Node& n : model_.nodes)
                for (int c : n.children)
                    if (c >= 0 && static_cast<size_t>(c) < isChild.size())
                        isChild[static_cast<size_t>(c)] = true;
            for (size_t i = 0; i < model_.nodes.size(); ++i)
                if (!isChild[i]) roots.push_back(static_cast<int>(i));
        }
        visited_.assign(model_.nodes.size(), false);
        for (int r : roots) visit(r, Affine3{}, "scene root");
        if (!scene_.faceUv.empty()) scene_.faceUv.resize(scene_.mesh.faces.size());
        warnTextureRepairs();
    }

    const std::vector<PrimitiveRange>& ranges() const { return ranges_; }

  private:
    [[noreturn]] void fail(const std::string& why) const { throw makeSceneError(file_, 0, why); }

    static double number(const std::vector<double>& v, size_t i, double fallback) {
        return i < v.size() ? v[i] : fallback;
    }

    void readMaterials() {
        for (size_t i = 0; i < model_.materials.size(); ++i) {
            const tinygltf::Material& g = model_.materials[i];
            const std::string where = "material " + std::to_string(i);
            const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
            const Vec3 base{number(pbr.baseColorFactor, 0, 1), number(pbr.baseColorFactor, 1, 1),
                            number(pbr.baseColorFactor, 2, 1)};
            const double metallic = pbr.metallicFactor;
            const double roughness = std::max(pbr.roughnessFactor, 0.01);
            double strength = 1;
            const auto ext = g.extensions.find("KHR_materials_emissive_strength");
            if (ext != g.extensions.end() && ext->second.Has("emissiveStrength")) {
                const tinygltf::Value& v = ext->second.Get("emissiveStrength");
                if (!v.IsNumber()) fail(where + ": emissiveStrength is not a number");
                strength = v.GetNumberAsDouble();
            }
            const Vec3 emissive{number(g.emissiveFactor, 0, 0), number(g.emissiveFactor, 1, 0),
                                number(g.emissiveFactor, 2, 0)};
            Material m;
            m.name = g.name.empty() ? "gltf_material_" + std::to_string(i) : g.name;
            m.kd = base * (1 - metallic);
            m.ks = Vec3{0.04, 0.04, 0.04} * (1 - metallic) + base * metallic;
            m.ns = 2 / std::pow(roughness, 4) - 2;
            m.ke = emissive * strength;
            m.kdMap = baseColorTexture(g, i, texCoordSet_.emplace_back(0));
            for (const Vec3& c : {base, emissive, m.kd, m.ks, m.ke}) {
                if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || c.x < 0 ||
                    c.y < 0 || c.z < 0) {
                    fail(where + ": colour factors must be finite and non-negative");
                }
            }
            if (!(metallic >= 0 && metallic <= 1) ||
                !(pbr.roughnessFactor >= 0 && pbr.roughnessFactor <= 1) || !(strength >= 0) ||
                !std::isfinite(strength)) {
                fail(where + ": metallic and roughness must lie in [0, 1], emissiveStrength >= 0");
            }
            scene_.materials.push_back(m);
        }
    }

    // A texture that cannot be used (repair mode: counted for one warning; strict: an error).
    struct TextureRepair {
        size_t count = 0;
        std::string first;
        void note(std::string what) {
            if (count++ == 0) first = std::move(what);
        }
    };

    void unusable(TextureRepair& repair, const std::string& what) {
        if (strict_)
            fail(what + " (repair mode uses the colour factor alone; strict mode refuses it)");
        repair.note(what);
    }

    void warnTextureRepairs() {
        if (unusableTextures_.count > 0)
            scene_.warnings.push_back(
                file_ + ": " + std::to_string(unusableTextures_.count) +
                " base-colour texture(s) cannot be used (first: " + unusableTextures_.first +
                "): their materials use the baseColorFactor alone");
        if (missingTexCoords_.count > 0)
            scene_.warnings.push_back(
                file_ + ": " + std::to_string(missingTexCoords_.count) +
                " primitive(s) lack the texture coordinates of their material's base-colour "
                "texture (first: " +
                missingTexCoords_.first + "): their faces use the baseColorFactor alone");
    }

    // The numbers of a KHR_texture_transform field: `count` numbers (1 for rotation).
    std::vector<double> numbers(const tinygltf::Value& ext, const char* key, size_t count,
                                const std::string& where) const {
        if (!ext.Has(key)) return {};
        const tinygltf::Value& v = ext.Get(key);
        std::vector<double> out;
        if (count == 1 && v.IsNumber()) {
            out.push_back(v.GetNumberAsDouble());
        } else if (count > 1 && v.IsArray() && v.ArrayLen() == count) {
            for (size_t i = 0; i < count; ++i)
                if (v.Get(static_cast<int>(i)).IsNumber())
                    out.push_back(v.Get(static_cast<int>(i)).GetNumberAsDouble());
        }
        for (double x : out)
            if (!std::isfinite(x)) out.clear();
        if (out.size() != count)
            fail(where + ": KHR_texture_transform " + key + " must be " +
                 (count == 1 ? std::string("a finite number")
                             : std::to_string(count) + " finite numbers"));
        return out;
    }

    // Material i's baseColorTexture as a TextureRef (its image decoded into scene.textures once),
    // and in texCoord the TEXCOORD set it reads; none when it has no such texture or the texture
    // cannot be used (unusable: a warning or, in strict mode, an error). A reference to a
    // texture, sampler or image that does not exist is an error (a broken file).
    TextureRef baseColorTexture(const tinygltf::Material& g, size_t i, int& texCoord) {
        const tinygltf::TextureInfo& info = g.pbrMetallicRoughness.baseColorTexture;
        if (info.index < 0) return {};
        const std::string where = "material " + std::to_string(i) +
                                  (g.name.empty() ? "" : " '" + g.name + "'") + " baseColorTexture";
        if (static_cast<size_t>(info.index) >= model_.textures.size())
            fail(where + ": texture " + std::to_string(info.index) + " does not exist");
        const tinygltf::Texture& texture = model_.textures[static_cast<size_t>(info.index)];
        TextureRef ref;
        texCoord = info.texCoord;
        if (const auto ext = info.extensions.find("KHR_texture_transform");
            ext != info.extensions.end()) {
            const tinygltf::Value& t = ext->second;
            if (const auto v = numbers(t, "offset", 2, where); !v.empty())
                ref.transform.offset = {v[0], v[1]};
            if (const auto v = numbers(t, "rotation", 1, where); !v.empty())
                ref.transform.rotation = v[0];
            if (const auto v = numbers(t, "scale", 2, where); !v.empty())
                ref.transform.scale = {v[0], v[1]};
            if (t.Has("texCoord")) {
                if (!t.Get("texCoord").IsInt() || t.Get("texCoord").GetNumberAsInt() < 0)
                    fail(where + ": KHR_texture_transform texCoord must be a non-negative integer");
                texCoord = t.Get("texCoord").GetNumberAsInt();
            }
        }
        if (texCoord < 0) fail(where + ": texCoord must be a non-negative integer");
        if (texture.sampler >= 0) {
            if (static_cast<size_t>(texture.sampler) >= model_.samplers.size())
                fail(where + ": sampler " + std::to_string(texture.sampler) + " does not exist");
            const tinygltf::Sampler& s = model_.samplers[static_cast<size_t>(texture.sampler)];
            const auto wrap = [](int w) {
                return w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? TextureWrap::ClampToEdge
                       : w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::MirroredRepeat
                                                                    : TextureWrap::Repeat;
            };
            ref.wrapU = wrap(s.wrapS);
            ref.wrapV = wrap(s.wrapT);
            if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) ref.filter = TextureFilter::Nearest;
        }
        if (texture.source < 0) {
            unusable(unusableTextures_,
                     where + ": texture " + std::to_string(info.index) +
                         " has no image in a decoded format (only in an extension's: basisu, "
                         "webp, avif, dds)");
            return {};
        }
        if (static_cast<size_t>(texture.source) >= model_.images.size())
            fail(where + ": image " + std::to_string(texture.source) + " does not exist");
        const int32_t image = decodedImage(texture.source, where);
        if (image < 0) return {};
        ref.image = image;
        return ref;
    }

    // glTF image `index` decoded into scene.textures (once); -1 when it cannot be (unusable).
    int32_t decodedImage(int index, const std::string& where) {
        const auto cached = imageTexture_.find(index);
        if (cached != imageTexture_.end()) {
            if (cached->second < 0)
                unusable(unusableTextures_,
                         where + ": image " + std::to_string(index) + ": " + imageProblem_[index]);
            return cached->second;
        }
        const tinygltf::Image& image = model_.images[static_cast<size_t>(index)];
        const std::string name = file_ + " image " + std::to_string(index);
        TextureRead read;
        if (image.bufferView >= 0) {
            if (static_cast<size_t>(image.bufferView) >= model_.bufferViews.size())
                fail("image " + std::to_string(index) + ": buffer view " +
                     std::to_string(image.bufferView) + " does not exist");
            const tinygltf::BufferView& bv =
                model_.bufferViews[static_cast<size_t>(image.bufferView)];
            if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model_.buffers.size())
                fail("image " + std::to_string(index) + ": buffer " + std::to_string(bv.buffer) +
                     " does not exist");
            const std::vector<unsigned char>& data =
                model_.buffers[static_cast<size_t>(bv.buffer)].data;
            if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
                fail("image " + std::to_string(index) +
                     ": buffer view reaches past the end of its buffer (" +
                     std::to_string(data.size()) + " bytes)");
            read = decodeTexture(
                std::span<const unsigned char>(data.data() + bv.byteOffset, bv.byteLength), name);
        } else if (!image.uri.empty()) {
            const fs::path path = directory_ / fs::path(percentDecoded(image.uri));
            read = readTextureFile(path);
            if (!read.image)
                read.problem = "'" + image.uri + "' (" + path.string() + "): " + read.problem;
        } else {
            read = decodeTexture(image.image, name);  // a data URI's bytes
        }
        int32_t texture = -1;
        if (read.image) {
            texture = static_cast<int32_t>(scene_.textures.size());
            scene_.textures.push_back(std::move(*read.image));
        } else {
            imageProblem_[index] = read.problem;
            unusable(unusableTextures_,
                     where + ": image " + std::to_string(index) + ": " + read.problem);
        }
        imageTexture_[index] = texture;
        return texture;
    }

    // The TEXCOORD_<set> of a primitive, one Uv per POSITION element (FLOAT, or normalised
    // UNSIGNED_BYTE / UNSIGNED_SHORT, VEC2); empty when the primitive lacks it (unusable).
    std::vector<Uv> texCoords(const tinygltf::Primitive& prim, int set, size_t count,
                              const std::string& where) {
        const std::string name = "TEXCOORD_" + std::to_string(set);
        const auto it = prim.attributes.find(name);
        if (it == prim.attributes.end()) {
            unusable(missingTexCoords_, where + ": no " + name + " attribute");
            return {};
        }
        const std::string aw = where + " " + name;
        if (it->second < 0 || static_cast<size_t>(it->second) >= model_.accessors.size())
            fail(aw + ": accessor " + std::to_string(it->second) + " does not exist");
        const tinygltf::Accessor& acc = model_.accessors[static_cast<size_t>(it->second)];
        const int ct = acc.componentType;
        const size_t component = ct == TINYGLTF_COMPONENT_TYPE_FLOAT            ? 4
                                 : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                 : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE  ? 1
                                                                                : 0;
        if (component == 0 || (component < 4 && !acc.normalized))
            fail(aw + ": must be FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
        const View view = accessorView(it->second, ct, TINYGLTF_TYPE_VEC2, 2 * component, aw);
        if (view.count != count)
            fail(aw + ": " + std::to_string(view.count) + " elements for " + std::to_string(count) +
                 " POSITION elements");
        std::vector<Uv> uvs(count);
        for (size_t i = 0; i < count; ++i) {
            const unsigned char* e = view.base + i * view.stride;
            double c[2];
            for (int k = 0; k < 2; ++k) {
                if (component == 4) {
                    float f;
                    std::memcpy(&f, e + 4 * k, 4);
                    c[k] = f;
                } else if (component == 2) {
                    uint16_t s;
                    std::memcpy(&s, e + 2 * k, 2);
                    c[k] = s / 65535.0;
                } else {
                    c[k] = e[k] / 255.0;
                }
            }
            if (!std::isfinite(c[0]) || !std::isfinite(c[1]))
                fail(aw + " " + std::to_string(i) + ": non-finite texture coordinate");
            uvs[i] = {c[0], c[1]};
        }
        return uvs;
    }

    Affine3 localTransform(const tinygltf::Node& n, const std::string& where) const {
        Affine3 a;
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16) fail(where + ": matrix must have 16 numbers");
            // Column-major 4x4.
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) a.m[r][c] = n.matrix[static_cast<size_t>(c * 4 + r)];
            if (n.matrix[3] != 0 || n.matrix[7] != 0 || n.matrix[11] != 0 || n.matrix[15] != 1)
                fail(where + ": matrix is not affine (its last row must be 0 0 0 1)");
        } else {
            if (!n.translation.empty() && n.translation.size() != 3)
                fail(where + ": translation must have 3 numbers");
            if (!n.rotation.empty() && n.rotation.size() != 4)
                fail(where + ": rotation must have 4 numbers");
            if (!n.scale.empty() && n.scale.size() != 3)
                fail(where + ": scale must have 3 numbers");
            Affine3 t, r, s;
            if (!n.translation.empty())
                t = Affine3::translation({n.translation[0], n.translation[1], n.translation[2]});
            if (!n.rotation.empty()) {
                const double len =
                    std::sqrt(n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                              n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3]);
                if (!(len > 0) || !std::isfinite(len))
                    fail(where + ": rotation is not a nonzero finite quaternion");
                r = Affine3::quaternion(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
            }
            if (!n.scale.empty()) s = Affine3::scaling({n.scale[0], n.scale[1], n.scale[2]});
            a = t * r * s;
        }
        if (!a.isFinite()) fail(where + ": non-finite transform");
        return a;
    }

    void visit(int index, const Affine3& parent, const std::string& from) {
        if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
            fail(from + ": node " + std::to_string(index) + " does not exist");
        if (visited_[static_cast<size_t>(index)]) {
            fail("node " + std::to_string(index) +
                 " is reached twice (the node hierarchy must be a tree)");
        }
        visited_[static_cast<size_t>(index)] = true;
        const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
        const std::string where = "node " + std::to_string(index);
        const Affine3 world = parent * localTransform(node, where);
        const double det = world.determinant();
        if (node.mesh >= 0) {
            if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
                fail(where + ": mesh " + std::to_string(node.mesh) + " does not exist");
            if (!(det != 0)) fail(where + ": singular transform (determinant 0)");
            const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(node.mesh)];
            for (size_t p = 0; p < mesh.primitives.size(); ++p)
                readPrimitive(index, node.mesh, static_cast<int>(p), world, det < 0);
        } else if (node.mesh < -1) {
            fail(where + ": mesh " + std::to_string(node.mesh) + " does not exist");
        }
        if (node.camera >= 0 && !scene_.camera) readCamera(node, world, where);
        for (int c : node.children) visit(c, world, where);
    }

    void readCamera(const tinygltf::Node& node, const Affine3& world, const std::string& where) {
        if (static_cast<size_t>(node.camera) >= model_.cameras.size())
            fail(where + ": camera " + std::to_string(node.camera) + " does not exist");
        const tinygltf::Camera& c = model_.cameras[static_cast<size_t>(node.camera)];
        if (c.type != "perspective") {
            scene_.warnings.push_back(file_ + ": " + where + ": " + c.type +
                                      " camera ignored (only perspective cameras are used)");
            return;
        }
        const double fov = c.perspective.yfov * 180 / std::numbers::pi;
        if (!(fov > 0 && fov < 180)) fail(where + ": camera yfov must lie in (0, pi)");
        Camera cam;
        cam.eye = world.point({0, 0, 0});
        const Vec3 forward = vis::normalize(world.vector({0, 0, -1}));
        const Vec3 up = vis::normalize(world.vector({0, 1, 0}));
        if (forward == Vec3{} || up == Vec3{}) fail(where + ": degenerate camera transform");
        cam.target = cam.eye + forward;
        cam.up = up;
        cam.fovYDegrees = fov;
        scene_.camera = cam;
    }

    // The bytes of accessor `a`: element i starts at base + i * stride and has elementSize bytes.
    struct View {
        const unsigned char* base = nullptr;
        size_t stride = 0;
        size_t count = 0;
    };

    View accessorView(int a, int componentType, int type, size_t elementSize,
                      const std::string& where) const {
        if (a < 0 || static_cast<size_t>(a) >= model_.accessors.size())
            fail(where + ": accessor " + std::to_string(a) + " does not exist");
        const tinygltf::Accessor& acc = model_.accessors[static_cast<size_t>(a)];
        const std::string what = where + " (accessor " + std::to_string(a) + ")";
        if (acc.sparse.isSparse) fail(what + ": sparse accessors are not supported");
        if (acc.componentType != componentType || acc.type != type)
            fail(what + ": unexpected component type or element type");
        if (acc.bufferView < 0 || static_cast<size_t>(acc.bufferView) >= model_.bufferViews.size())
            fail(what + ": buffer view " + std::to_string(acc.bufferView) + " does not exist");
        const tinygltf::BufferView& bv = model_.bufferViews[static_cast<size_t>(acc.bufferView)];
        if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model_.buffers.size())
            fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
        const tinygltf::Buffer& buffer = model_.buffers[static_cast<size_t>(bv.buffer)];
        if (bv.byteOffset > buffer.data.size() ||
            bv.byteLength > buffer.data.size() - bv.byteOffset)
            fail(what + ": buffer view reaches past the end of its buffer (" +
                 std::to_string(buffer.data.size()) + " bytes)");
        const size_t stride = bv.byteStride == 0 ? elementSize : bv.byteStride;
        if (stride < elementSize) fail(what + ": byteStride smaller than an element");
        View view;
        view.count = acc.count;
        view.stride = stride;
        if (acc.count > 0) {
            // Needs byteOffset + (count - 1) * stride + elementSize <= byteLength, without
            // overflow.
            const size_t avail =
                acc.byteOffset <= bv.byteLength ? bv.byteLength - acc.byteOffset : 0;
            if (avail < elementSize || (acc.count - 1) > (avail - elementSize) / stride) {
                fail(what + ": " + std::to_string(acc.count) +
                     " elements reach past the end of the buffer view (" +
                     std::to_string(bv.byteLength) + " bytes)");
            }
        }
        view.base = buffer.data.data() + bv.byteOffset + acc.byteOffset;
        return view;
    }

    void readPrimitive(int nodeIndex, int meshIndex, int p, const Affine3& world, bool flip) {
        const tinygltf::Primitive& prim =
            model_.meshes[static_cast<size_t>(meshIndex)].primitives[static_cast<size_t>(p)];
        const std::string where = "node " + std::to_string(nodeIndex) + " mesh " +
                                  std::to_string(meshIndex) + " primitive " + std::to_string(p);
        const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode < TINYGLTF_MODE_TRIANGLES || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
            if (mode >= 0 && mode < TINYGLTF_MODE_TRIANGLES) {
                scene_.warnings.push_back(file_ + ": " + where +
                                          ": point/line primitive skipped (no faces)");
                return;
            }
            fail(where + ": unknown mode " + std::to_string(mode));
        }
        const auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) fail(where + ": no POSITION attribute");
        const View positions = accessorView(pos->second, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                            TINYGLTF_TYPE_VEC3, 12, where + " POSITION");
        if (prim.material < -1 || prim.material >= static_cast<int>(scene_.materials.size()))
            fail(where + ": material " + std::to_string(prim.material) + " does not exist");

        std::vector<uint32_t> indices;
        if (prim.indices >= 0) {
            const std::string iw = where + " indices";
            if (static_cast<size_t>(prim.indices) >= model_.accessors.size())
                fail(iw + ": accessor " + std::to_string(prim.indices) + " does not exist");
            const int ct = model_.accessors[static_cast<size_t>(prim.indices)].componentType;
            const size_t size = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                                : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                               : 0;
            if (size == 0)
                fail(iw + ": indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
            const View view = accessorView(prim.indices, ct, TINYGLTF_TYPE_SCALAR, size, iw);
            indices.resize(view.count);
            for (size_t i = 0; i < view.count; ++i) {
                const unsigned char* e = view.base + i * view.stride;
                uint32_t v = 0;
                if (size == 1) {
                    v = e[0];
                } else if (size == 2) {
                    uint16_t s;
                    std::memcpy(&s, e, 2);
                    v = s;
                } else {
                    std::memcpy(&v, e, 4);
                }
                if (v >= positions.count) {
                    fail(iw + ": index " + std::to_string(i) + " is " + std::to_string(v) +
                         ", out of range (POSITION has " + std::to_string(positions.count) +
                         " elements)");
                }
                indices[i] = v;
            }
        } else {
            if (positions.count > kMaxSceneElements) fail(where + ": too many vertices");
            indices.resize(positions.count);
            for (size_t i = 0; i < positions.count; ++i) indices[i] = static_cast<uint32_t>(i);
        }

        const size_t offset = scene_.mesh.vertices.size();
        if (offset + positions.count > kMaxSceneElements) fail(where + ": too many vertices");
        for (size_t i = 0; i < positions.count; ++i) {
            float f[3];
            std::memcpy(f, positions.base + i * positions.stride, sizeof f);
            if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
                fail(where + ": POSITION " + std::to_string(i) + ": non-finite coordinate");
            scene_.mesh.vertices.push_back(world.point({f[0], f[1], f[2]}));
        }

        // Texture coordinates where the primitive's material has a base-colour texture.
        std::vector<Uv> uvs;
        if (prim.material >= 0 &&
            scene_.materials[static_cast<size_t>(prim.material)].kdMap.present())
            uvs = texCoords(prim, texCoordSet_[static_cast<size_t>(prim.material)], positions.count,
                            where);

        ranges_.push_back(
            {static_cast<uint32_t>(scene_.mesh.faces.size()), nodeIndex, meshIndex, p});
        const auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
            const auto o = static_cast<uint32_t>(offset);
            if (flip) std::swap(b, c);
            if (!uvs.empty()) {
                // Faces before it without coordinates get none; later ones the same (read()).
                scene_.faceUv.resize(scene_.mesh.faces.size());
                scene_.faceUv.push_back({uvs[a], uvs[b], uvs[c]});
            }
            scene_.mesh.faces.push_back({a + o, b + o, c + o});
            scene_.faceMaterial.push_back(prim.material);
        };
        const size_t n = indices.size();
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (n % 3 != 0) {
                fail(where + ": " + std::to_string(n) +
                     " vertices, not a multiple of 3 (TRIANGLES)");
            }
            for (size_t i = 0; i + 2 < n; i += 3) add(indices[i], indices[i + 1], indices[i + 2]);
        } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // Every other triangle of a strip is reversed so that all keep the first's winding.
            for (size_t i = 0; i + 2 < n; ++i) {
                if (i % 2 == 0)
                    add(indices[i], indices[i + 1], indices[i + 2]);
                else
                    add(indices[i + 1], indices[i], indices[i + 2]);
            }
        } else {
            for (size_t i = 1; i + 1 < n; ++i) add(indices[0], indices[i], indices[i + 1]);
        }
        if (scene_.mesh.faces.size() > kMaxSceneElements) fail(where + ": too many faces");
    }

    const tinygltf::Model& model_;
    std::string file_;
    fs::path directory_;  // where URIs resolve
    bool strict_ = false;
    Scene& scene_;
    std::vector<bool> visited_;
    std::vector<PrimitiveRange> ranges_;
    std::vector<int> texCoordSet_;  // per material: the TEXCOORD set its base colour reads
    std::unordered_map<int, int32_t> imageTexture_;      // glTF image -> scene texture (-1: none)
    std::unordered_map<int, std::string> imageProblem_;  // why an image is none
    TextureRepair unusableTextures_, missingTexCoords_;
};

}  // namespace

Scene loadGltf(const fs::path& path, const LoadOptions& options) {
    const std::string file = path.string();
    const std::string data = readSceneFile(path);
    if (data.empty()) throw makeSceneError(file, 0, "empty file");
    if (data.size() > 0x7fffffffu) throw makeSceneError(file, 0, "file too large for tinygltf");

    const bool binary = data.compare(0, 4, "glTF") == 0;
    checkVersionAndExtensions(data, binary, file);

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepImageBytes, nullptr);
    loader.SetFsCallbacks({pathExists, samePath, readRegularFile, refuseWrite, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const std::string baseDir = path.parent_path().string();
    bool ok = false;
    try {
        ok = binary ? loader.LoadBinaryFromMemory(
                          &model, &err, &warn, reinterpret_cast<const unsigned char*>(data.data()),
                          static_cast<unsigned int>(data.size()), baseDir)
                    : loader.LoadASCIIFromString(&model, &err, &warn, data.data(),
                                                 static_cast<unsigned int>(data.size()), baseDir);
    } catch (const std::exception& e) {
        // tinygltf itself throws on some malformed files (found by fuzzing: an index checked
        // with vector::at on an empty array): still an error about this file.
        throw makeSceneError(file, 0,
                             std::string(binary ? "GLB" : "glTF") +
                                 ": tinygltf failed on the file (" + e.what() + ")");
    }
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        throw makeSceneError(file, 0,
                             std::string(binary ? "GLB" : "glTF") + ": " +
                                 (err.empty() ? "tinygltf could not parse the file" : err));
    }

    Scene scene;
    scene.sourcePath = file;
    GltfReader reader(model, file, path.parent_path(), options.strict, scene);
    reader.read();
    if (scene.mesh.faces.empty())
        throw makeSceneError(file, 0, "no faces (no triangle primitives)");
    const std::vector<PrimitiveRange> ranges = reader.ranges();
    const FaceNamer namer = [ranges](uint32_t f) {
        const auto it = std::upper_bound(
            ranges.begin(), ranges.end(), f,
            [](uint32_t face, const PrimitiveRange& r) { return face < r.firstFace; });
        const PrimitiveRange& r = *(it - 1);
        return "node " + std::to_string(r.node) + " mesh " + std::to_string(r.mesh) +
               " primitive " + std::to_string(r.primitive) + " triangle " +
               std::to_string(f - r.firstFace);
    };
    while (!warn.empty() && (warn.back() == '\n' || warn.back() == ' ')) warn.pop_back();
    if (!warn.empty()) scene.warnings.push_back(file + ": tinygltf: " + warn);
    checkLoadedFaces(scene, options.faces, namer);
    return scene;
}

}  // namespace penumbra
