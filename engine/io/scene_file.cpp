#include "engine/io/scene_file.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/io/text_input.h"
#include "engine/scene/affine3.h"
#include "engine/scene/face_check.h"
#include "engine/scene/light_move.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class SceneFileReader {
  public:
    SceneFileReader(std::string file, fs::path baseDirectory, const LoadOptions& options)
        : file_(std::move(file)), base_(std::move(baseDirectory)), options_(options) {}

    Scene read(std::string_view text) {
        const Json root = parse(text);
        if (!root.is_object()) fail("(root)", "expected a JSON object");
        allowKeys(root, "(root)",
                  {"meshes", "polygons", "area_lights", "point_lights", "moved_lights", "camera",
                   "strict", "comment"});
        scene_.sourcePath = file_;
        if (root.contains("strict")) strict_ = boolean(root["strict"], "strict");

        std::optional<Camera> meshCamera;
        if (root.contains("meshes")) {
            const Json& meshes = array(root["meshes"], "meshes");
            for (size_t i = 0; i < meshes.size(); ++i) {
                addMesh(meshes[i], "meshes[" + std::to_string(i) + "]", meshCamera);
            }
        }
        if (root.contains("polygons")) addPolygons(array(root["polygons"], "polygons"));
        if (root.contains("area_lights")) addAreaLights(array(root["area_lights"], "area_lights"));
        if (root.contains("point_lights"))
            addPointLights(array(root["point_lights"], "point_lights"));
        if (root.contains("camera")) {
            scene_.camera = camera(root["camera"], "camera");
        } else if (meshCamera) {
            scene_.camera = meshCamera;
        }
        if (scene_.mesh.faces.empty())
            fail("(root)", "no faces (no meshes, polygons or area lights)");
        // Texture coordinates: one entry per face once any mesh has them (the polygons have none).
        if (!scene_.faceUv.empty()) scene_.faceUv.resize(scene_.mesh.faces.size());
        validateSceneStructure(scene_);
        scene_.collectLights();
        if (root.contains("moved_lights")) moveLights(array(root["moved_lights"], "moved_lights"));
        return std::move(scene_);
    }

  private:
    // The JSON text parsed; a syntax error names its line, a number beyond the double range
    // (1e309) the line of its first occurrence and its JSON path.
    Json parse(std::string_view text) const {
        // Where the parser is (a JSON path), for the one error nlohmann reports without a
        // position: a number beyond the double range (1e309).
        struct Frame {
            bool array = false;
            std::string key;
            size_t count = 0;
        };
        std::vector<Frame> frames;
        auto where = [&] {
            std::string path;
            for (const Frame& f : frames)
                path += f.array ? "[" + std::to_string(f.count) + "]"
                                : (path.empty() ? "" : ".") + f.key;
            return path.empty() ? std::string("(root)") : path;
        };
        const Json::parser_callback_t track = [&](int, Json::parse_event_t event, Json& parsed) {
            using E = Json::parse_event_t;
            auto done = [&] {
                if (!frames.empty() && frames.back().array) ++frames.back().count;
            };
            switch (event) {
                case E::object_start:
                case E::array_start:
                    frames.push_back({event == E::array_start, {}, 0});
                    break;
                case E::key:
                    if (!frames.empty() && parsed.is_string())
                        frames.back().key = parsed.get<std::string>();
                    break;
                case E::object_end:
                case E::array_end:
                    if (!frames.empty()) frames.pop_back();
                    done();
                    break;
                case E::value:
                    done();
                    break;
            }
            return true;
        };
        try {
            return Json::parse(text.begin(), text.end(), track);
        } catch (const Json::parse_error& e) {
            int64_t line = 1;
            for (size_t i = 0; i < std::min<size_t>(e.byte, text.size()); ++i)
                line += text[i] == '\n';
            throw makeSceneError(file_, line, std::string("JSON syntax error: ") + e.what());
        } catch (const Json::out_of_range& e) {
            // "number overflow parsing '1e309'": the line of that token's first occurrence.
            const std::string message = e.what();
            const size_t open = message.find('\''), close = message.rfind('\'');
            const std::string token = open != std::string::npos && close > open
                                          ? message.substr(open + 1, close - open - 1)
                                          : std::string();
            int64_t line = 0;
            if (const size_t at = token.empty() ? std::string_view::npos : text.find(token);
                at != std::string_view::npos) {
                line = 1;
                for (size_t i = 0; i < at; ++i) line += text[i] == '\n';
            }
            throw makeSceneError(
                file_, line,
                where() + ": the number " + token + " is beyond the range of a double");
        }
    }

    // "polygons": each with its own material (default: named polygon_I).
    void addPolygons(const Json& polygons) {
        for (size_t i = 0; i < polygons.size(); ++i) {
            const std::string path = "polygons[" + std::to_string(i) + "]";
            const Json& p = object(polygons[i], path);
            allowKeys(p, path, {"vertices", "material", "comment"});
            Material m;
            m.name = "polygon_" + std::to_string(i);
            if (p.contains("material")) m = material(p["material"], path + ".material", m);
            addPolygon(p, path, m);
        }
    }

    // "area_lights": polygons with a nonzero emission.
    void addAreaLights(const Json& lights) {
        for (size_t i = 0; i < lights.size(); ++i) {
            const std::string path = "area_lights[" + std::to_string(i) + "]";
            const Json& l = object(lights[i], path);
            allowKeys(l, path, {"vertices", "emission", "kd", "comment"});
            Material m;
            m.name = "area_light_" + std::to_string(i);
            if (!l.contains("emission")) fail(path, "missing \"emission\"");
            m.ke = color(l["emission"], path + ".emission");
            if (!m.isEmissive()) fail(path + ".emission", "must be nonzero");
            if (l.contains("kd")) m.kd = color(l["kd"], path + ".kd");
            addPolygon(l, path, m);
        }
    }

    // "moved_lights": lights (numbered as the scene numbers them, file order) placed at new
    // vertices, as the viewer saves a moved light (engine/scene/light_move.h: checked, never
    // repaired).
    void moveLights(const Json& moved) {
        for (size_t i = 0; i < moved.size(); ++i) {
            const std::string path = "moved_lights[" + std::to_string(i) + "]";
            const Json& m = object(moved[i], path);
            allowKeys(m, path, {"light", "vertices", "comment"});
            if (!m.contains("light")) fail(path, "missing \"light\"");
            if (!m["light"].is_number_unsigned())
                fail(path + ".light", "expected a light number (0, 1, ...)");
            const uint64_t light = m["light"].get<uint64_t>();
            if (light >= scene_.lights.size())
                fail(path + ".light", "no light " + std::to_string(light) + " (the scene has " +
                                          std::to_string(scene_.lights.size()) + ")");
            if (!m.contains("vertices")) fail(path, "missing \"vertices\"");
            const Json& vs = array(m["vertices"], path + ".vertices");
            std::vector<Vec3> vertices;
            for (size_t k = 0; k < vs.size(); ++k)
                vertices.push_back(vec3(vs[k], path + ".vertices[" + std::to_string(k) + "]"));
            placeLight(scene_, static_cast<uint32_t>(light), vertices, path);
        }
    }

    void addPointLights(const Json& lights) {
        for (size_t i = 0; i < lights.size(); ++i) {
            const std::string path = "point_lights[" + std::to_string(i) + "]";
            const Json& l = object(lights[i], path);
            allowKeys(l, path, {"position", "intensity", "comment"});
            PointLight light;
            if (!l.contains("position")) fail(path, "missing \"position\"");
            light.position = vec3(l["position"], path + ".position");
            if (l.contains("intensity"))
                light.intensity = color(l["intensity"], path + ".intensity");
            scene_.pointLights.push_back(light);
        }
    }

    [[noreturn]] void fail(const std::string& path, const std::string& why) const {
        throw makeSceneError(file_, 0, path + ": " + why);
    }

    void allowKeys(const Json& o, const std::string& path,
                   std::initializer_list<const char*> keys) const {
        for (auto it = o.begin(); it != o.end(); ++it) {
            bool known = false;
            for (const char* k : keys) known = known || it.key() == k;
            if (!known) {
                std::string list;
                for (const char* k : keys) list += std::string(list.empty() ? "" : ", ") + k;
                fail(path, "unknown key \"" + it.key() + "\" (allowed: " + list + ")");
            }
        }
    }

    bool boolean(const Json& j, const std::string& path) const {
        if (!j.is_boolean()) fail(path, "expected true or false");
        return j.get<bool>();
    }
    const Json& array(const Json& j, const std::string& path) const {
        if (!j.is_array()) fail(path, "expected an array");
        return j;
    }
    const Json& object(const Json& j, const std::string& path) const {
        if (!j.is_object()) fail(path, "expected an object");
        return j;
    }
    double number(const Json& j, const std::string& path) const {
        if (!j.is_number()) fail(path, "expected a number");
        const double v = j.get<double>();
        if (!std::isfinite(v)) fail(path, "expected a finite number");
        return v;
    }
    Vec3 vec3(const Json& j, const std::string& path) const {
        if (!j.is_array() || j.size() != 3) fail(path, "expected 3 numbers");
        return {number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]")};
    }
    // A number for all three components, or 3 numbers.
    Vec3 vec3OrScalar(const Json& j, const std::string& path) const {
        if (j.is_number()) {
            const double v = number(j, path);
            return {v, v, v};
        }
        if (!j.is_array() || j.size() != 3) fail(path, "expected a number or 3 numbers");
        return vec3(j, path);
    }
    Vec3 color(const Json& j, const std::string& path) const {
        const Vec3 c = vec3OrScalar(j, path);
        if (c.x < 0 || c.y < 0 || c.z < 0) fail(path, "colours must be non-negative");
        return c;
    }

    Material material(const Json& j, const std::string& path, Material m) const {
        object(j, path);
        allowKeys(j, path, {"name", "kd", "ks", "ke", "ns", "comment"});
        if (j.contains("name")) {
            if (!j["name"].is_string() || j["name"].get<std::string>().empty())
                fail(path + ".name", "expected a non-empty string");
            m.name = j["name"].get<std::string>();
        }
        if (j.contains("kd")) m.kd = color(j["kd"], path + ".kd");
        if (j.contains("ks")) m.ks = color(j["ks"], path + ".ks");
        if (j.contains("ke")) m.ke = color(j["ke"], path + ".ke");
        if (j.contains("ns")) {
            m.ns = number(j["ns"], path + ".ns");
            if (m.ns < 0) fail(path + ".ns", "must be non-negative");
        }
        return m;
    }

    Camera camera(const Json& j, const std::string& path) const {
        object(j, path);
        allowKeys(j, path, {"eye", "target", "up", "fov_y", "comment"});
        Camera c;
        if (!j.contains("eye") || !j.contains("target")) fail(path, "needs \"eye\" and \"target\"");
        c.eye = vec3(j["eye"], path + ".eye");
        c.target = vec3(j["target"], path + ".target");
        if (j.contains("up")) c.up = vec3(j["up"], path + ".up");
        if (j.contains("fov_y")) c.fovYDegrees = number(j["fov_y"], path + ".fov_y");
        if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180))
            fail(path + ".fov_y", "must lie strictly between 0 and 180 degrees");
        const Vec3 forward = c.target - c.eye;
        if (forward == Vec3{}) fail(path, "eye and target coincide");
        if (vis::cross(forward, c.up) == Vec3{})
            fail(path + ".up", "zero or parallel to the view direction");
        return c;
    }

    Affine3 transformStep(const Json& j, const std::string& path) const {
        object(j, path);
        if (j.contains("matrix")) {
            allowKeys(j, path, {"matrix", "comment"});
            const Json& m = j["matrix"];
            const std::string mp = path + ".matrix";
            if (!m.is_array() || m.size() != 4) fail(mp, "expected 4 rows of 4 numbers");
            Affine3 a;
            double last[4];
            for (size_t r = 0; r < 4; ++r) {
                const std::string rp = mp + "[" + std::to_string(r) + "]";
                if (!m[r].is_array() || m[r].size() != 4) fail(rp, "expected 4 numbers");
                for (size_t c = 0; c < 4; ++c) {
                    const double v = number(m[r][c], rp + "[" + std::to_string(c) + "]");
                    if (r < 3)
                        a.m[r][c] = v;
                    else
                        last[c] = v;
                }
            }
            if (last[0] != 0 || last[1] != 0 || last[2] != 0 || last[3] != 1)
                fail(mp + "[3]", "the last row must be [0, 0, 0, 1] (affine transforms only)");
            return a;
        }
        allowKeys(j, path, {"scale", "rotate", "translate", "comment"});
        Affine3 a;
        if (j.contains("scale")) a = Affine3::scaling(vec3OrScalar(j["scale"], path + ".scale"));
        if (j.contains("rotate")) {
            const std::string rp = path + ".rotate";
            const Json& r = object(j["rotate"], rp);
            allowKeys(r, rp, {"axis", "degrees"});
            if (!r.contains("axis") || !r.contains("degrees"))
                fail(rp, "needs \"axis\" and \"degrees\"");
            const Vec3 axis = vec3(r["axis"], rp + ".axis");
            if (axis == Vec3{}) fail(rp + ".axis", "must be nonzero");
            a = Affine3::rotation(axis,
                                  number(r["degrees"], rp + ".degrees") * std::numbers::pi / 180) *
                a;
        }
        if (j.contains("translate"))
            a = Affine3::translation(vec3(j["translate"], path + ".translate")) * a;
        return a;
    }

    Affine3 transform(const Json& j, const std::string& path) const {
        Affine3 a;
        if (j.is_array()) {
            for (size_t i = 0; i < j.size(); ++i)
                a = transformStep(j[i], path + "[" + std::to_string(i) + "]") * a;
        } else if (j.is_object()) {
            a = transformStep(j, path);
        } else {
            fail(path, "expected an object or an array of objects");
        }
        if (!a.isFinite()) fail(path, "non-finite transform");
        return a;
    }

    // The uniform scale + translation that puts `box` (non-empty) into the fit_into box.
    Affine3 fitInto(const Json& j, const std::string& path, const vis::Bounds3& box) const {
        object(j, path);
        allowKeys(j, path, {"min", "max", "align", "comment"});
        if (!j.contains("min") || !j.contains("max")) fail(path, "needs \"min\" and \"max\"");
        const Vec3 lo = vec3(j["min"], path + ".min"), hi = vec3(j["max"], path + ".max");
        int align[3] = {0, 0, 0};  // -1 min, 0 center, +1 max
        if (j.contains("align")) {
            const Json& a = j["align"];
            if (!a.is_array() || a.size() != 3) fail(path + ".align", "expected 3 strings");
            for (size_t i = 0; i < 3; ++i) {
                const std::string ap = path + ".align[" + std::to_string(i) + "]";
                const std::string s = a[i].is_string() ? a[i].get<std::string>() : "";
                if (s == "min")
                    align[i] = -1;
                else if (s == "center")
                    align[i] = 0;
                else if (s == "max")
                    align[i] = 1;
                else
                    fail(ap, "expected \"min\", \"center\" or \"max\"");
            }
        }
        double scale = INFINITY;
        for (int i = 0; i < 3; ++i) {
            if (!(hi[i] >= lo[i])) fail(path, "max must not be below min");
            const double extent = box.hi[i] - box.lo[i];
            if (extent > 0) scale = std::min(scale, (hi[i] - lo[i]) / extent);
        }
        if (!(scale > 0) || !std::isfinite(scale))
            fail(path, "the box has zero extent along an axis the mesh spans");
        Vec3 t;
        double tv[3];
        for (int i = 0; i < 3; ++i) {
            if (align[i] < 0)
                tv[i] = lo[i] - scale * box.lo[i];
            else if (align[i] > 0)
                tv[i] = hi[i] - scale * box.hi[i];
            else
                tv[i] = (lo[i] + hi[i]) / 2 - scale * (box.lo[i] + box.hi[i]) / 2;
        }
        t = {tv[0], tv[1], tv[2]};
        return Affine3::translation(t) * Affine3::scaling({scale, scale, scale});
    }

    std::string uniqueMaterialName(const std::string& name) {
        std::string unique = name;
        for (int n = 2; !materialNames_.insert(unique).second; ++n)
            unique = name + "_" + std::to_string(n);
        return unique;
    }

    void addMesh(const Json& j, const std::string& path, std::optional<Camera>& meshCamera) {
        object(j, path);
        allowKeys(j, path,
                  {"file", "transform", "fit_into", "material", "materials", "strict",
                   "drop_degenerate_faces", "comment"});
        if (!j.contains("file") || !j["file"].is_string() || j["file"].get<std::string>().empty())
            fail(path + ".file", "expected a file name");
        const std::string name = j["file"].get<std::string>();
        const fs::path meshPath = base_ / fs::path(name);
        const std::string ext = lowerExtension(meshPath);
        if (ext == ".json") fail(path + ".file", "a scene file cannot include another scene file");
        if (!isSupportedSceneExtension(ext)) {
            fail(path + ".file", "unknown format '" + ext + "' (supported: " +
                                     supportedSceneExtensions() + ", except .json)");
        }
        const LoadOptions options = meshOptions(j, path);
        // Validate the entry before the (possibly slow) load.
        Affine3 toWorld;
        if (j.contains("transform")) toWorld = transform(j["transform"], path + ".transform");
        std::optional<Material> single;
        if (j.contains("material")) {
            Material m;
            m.name = "mesh_" + std::to_string(meshIndex_);
            single = material(j["material"], path + ".material", m);
        }
        const Json* overrides = nullptr;
        if (j.contains("materials")) overrides = &object(j["materials"], path + ".materials");
        std::error_code ec;
        if (!fs::is_regular_file(meshPath, ec)) {
            // Not there at all (a mesh not fetched yet), or something else (a directory).
            if (!fs::exists(meshPath, ec))
                throw makeMissingFileError(file_, 0,
                                           path + ".file: no such file: " + meshPath.string(),
                                           meshPath.string());
            fail(path + ".file", "no such file: " + meshPath.string());
        }

        Scene part;
        try {
            part = loadScenePart(meshPath, options);
        } catch (const SceneError& e) {
            fail(path, e.what());
        }
        for (std::string& w : part.warnings)
            scene_.warnings.push_back(file_ + ": " + path + ": " + w);
        part.warnings.clear();

        if (j.contains("fit_into")) {
            vis::Bounds3 box;
            for (const auto& face : part.mesh.faces)
                for (uint32_t v : face) box.add(toWorld.point(part.mesh.vertices[v]));
            toWorld = fitInto(j["fit_into"], path + ".fit_into", box) * toWorld;
        }
        place(part, toWorld, path, meshCamera);
        if (overrides) overrideMaterials(part, *overrides, path, meshPath);
        if (single) {
            part.materials = {*single};
            part.faceMaterial.assign(part.mesh.faces.size(), 0);
        }

        // Transformed geometry is rounded: check the faces again, in the file's terms.
        part.sourcePath = file_;
        part.faceSourceLine.clear();
        const std::string label = path + " (" + name + ")";
        checkLoadedFaces(part, options.faces,
                         [&label](uint32_t f) { return label + " face " + std::to_string(f); });
        for (std::string& w : part.warnings) scene_.warnings.push_back(w);
        append(std::move(part), path);
        ++meshIndex_;
    }

    // The caller's options (the command line's --strict), made strict by the file's or the
    // entry's "strict"; "drop_degenerate_faces" then decides the faces alone.
    LoadOptions meshOptions(const Json& j, const std::string& path) const {
        LoadOptions options = options_;
        const bool strict = j.contains("strict") ? boolean(j["strict"], path + ".strict") : strict_;
        if (strict) options = LoadOptions::strictMode();
        if (j.contains("drop_degenerate_faces")) {
            options.faces = boolean(j["drop_degenerate_faces"], path + ".drop_degenerate_faces")
                                ? DegenerateFaces::kDrop
                                : DegenerateFaces::kReject;
        }
        return options;
    }

    // A mesh's vertices, camera and point lights taken to the world (a mirroring transform
    // reverses its faces, to keep them facing out); its camera is the scene's when it is the first.
    void place(Scene& part, const Affine3& toWorld, const std::string& path,
               std::optional<Camera>& meshCamera) {
        const double det = toWorld.determinant();
        if (!(det != 0) || !std::isfinite(det)) fail(path + ".transform", "singular transform");
        for (Vec3& v : part.mesh.vertices) v = toWorld.point(v);
        if (det < 0) {
            for (auto& face : part.mesh.faces) std::reverse(face.begin() + 1, face.end());
            for (auto& uvs : part.faceUv)
                if (!uvs.empty()) std::reverse(uvs.begin() + 1, uvs.end());
        }
        if (part.camera) {
            Camera c = *part.camera;
            const Vec3 up = toWorld.vector(c.up);
            c.eye = toWorld.point(c.eye);
            c.target = toWorld.point(c.target);
            c.up = up;
            if (!meshCamera) meshCamera = c;
        }
        for (PointLight& l : part.pointLights) {
            l.position = toWorld.point(l.position);
            scene_.pointLights.push_back(l);
        }
    }

    // "materials": each named material of the mesh changed by the entry's fields.
    void overrideMaterials(Scene& part, const Json& overrides, const std::string& path,
                           const fs::path& meshPath) const {
        for (auto it = overrides.begin(); it != overrides.end(); ++it) {
            const std::string op = path + ".materials." + it.key();
            auto m = std::find_if(part.materials.begin(), part.materials.end(),
                                  [&](const Material& x) { return x.name == it.key(); });
            if (m == part.materials.end())
                fail(op, "no material named '" + it.key() + "' in " + meshPath.string());
            *m = material(it.value(), op, *m);
        }
    }

    // The mesh appended to the scene: its vertices, faces (with their texture coordinates),
    // materials (renamed where a name is taken) and textures after those already there.
    void append(Scene part, const std::string& path) {
        const auto vertexOffset = static_cast<uint32_t>(scene_.mesh.vertices.size());
        const auto materialOffset = static_cast<int32_t>(scene_.materials.size());
        const auto textureOffset = static_cast<int32_t>(scene_.textures.size());
        if (scene_.mesh.vertices.size() + part.mesh.vertices.size() > kMaxSceneElements ||
            scene_.mesh.faces.size() + part.mesh.faces.size() > kMaxSceneElements)
            fail(path, "too many vertices or faces in the composed scene");
        for (Material& m : part.materials) {
            m.name = uniqueMaterialName(m.name);
            if (m.kdMap.present()) m.kdMap.image += textureOffset;
            scene_.materials.push_back(std::move(m));
        }
        for (TextureImage& t : part.textures) scene_.textures.push_back(std::move(t));
        if (!part.faceUv.empty() || !scene_.faceUv.empty()) {
            scene_.faceUv.resize(scene_.mesh.faces.size());
            part.faceUv.resize(part.mesh.faces.size());
            for (std::vector<Uv>& uvs : part.faceUv) scene_.faceUv.push_back(std::move(uvs));
        }
        scene_.mesh.vertices.insert(scene_.mesh.vertices.end(), part.mesh.vertices.begin(),
                                    part.mesh.vertices.end());
        for (size_t f = 0; f < part.mesh.faces.size(); ++f) {
            std::vector<uint32_t>& face = part.mesh.faces[f];
            for (uint32_t& v : face) v += vertexOffset;
            scene_.mesh.faces.push_back(std::move(face));
            const int32_t m = f < part.faceMaterial.size() ? part.faceMaterial[f] : -1;
            scene_.faceMaterial.push_back(m < 0 ? -1 : m + materialOffset);
        }
    }

    // A polygon ("vertices") with material m, checked on its own.
    void addPolygon(const Json& j, const std::string& path, Material m) {
        if (!j.contains("vertices")) fail(path, "missing \"vertices\"");
        const Json& vs = array(j["vertices"], path + ".vertices");
        if (vs.size() < 3) fail(path + ".vertices", "a polygon needs at least 3 vertices");
        Scene part;
        part.sourcePath = file_;
        std::vector<uint32_t> face;
        for (size_t i = 0; i < vs.size(); ++i) {
            part.mesh.vertices.push_back(
                vec3(vs[i], path + ".vertices[" + std::to_string(i) + "]"));
            face.push_back(static_cast<uint32_t>(i));
        }
        part.mesh.faces.push_back(face);
        checkLoadedFaces(part, DegenerateFaces::kReject, [&path](uint32_t) { return path; });

        const auto offset = static_cast<uint32_t>(scene_.mesh.vertices.size());
        for (uint32_t& v : face) v += offset;
        scene_.mesh.vertices.insert(scene_.mesh.vertices.end(), part.mesh.vertices.begin(),
                                    part.mesh.vertices.end());
        scene_.mesh.faces.push_back(std::move(face));
        m.name = uniqueMaterialName(m.name);
        scene_.materials.push_back(std::move(m));
        scene_.faceMaterial.push_back(static_cast<int32_t>(scene_.materials.size() - 1));
    }

    std::string file_;
    fs::path base_;
    LoadOptions options_;
    bool strict_ = false;  // the file's "strict"
    Scene scene_;
    std::unordered_set<std::string> materialNames_;
    int meshIndex_ = 0;
};

}  // namespace

Scene loadJsonScene(const fs::path& path, const LoadOptions& options) {
    const std::string file = path.string();
    return loadJsonSceneFromString(readSceneFile(path), path.parent_path(), file, options);
}

Scene loadJsonSceneFromString(std::string_view json, const fs::path& baseDirectory,
                              std::string sourceName, const LoadOptions& options) {
    SceneFileReader reader(std::move(sourceName), baseDirectory, options);
    return reader.read(json);
}

std::string jsonSceneWithCamera(const std::filesystem::path& source, const Camera& camera,
                                const std::filesystem::path& target,
                                const DefaultLight* defaultLight,
                                std::span<const PlacedLight> movedLights) {
    namespace fs = std::filesystem;
    const fs::path targetDir = fs::absolute(target).parent_path();
    // A path as the new file names it: relative to its directory (absolute when there is no
    // relative form, e.g. another drive).
    auto rebased = [&](const fs::path& absolutePath) {
        const fs::path r = absolutePath.lexically_normal().lexically_relative(targetDir);
        return (r.empty() ? absolutePath.lexically_normal() : r).generic_string();
    };
    const fs::path sourceDir = fs::absolute(source).parent_path();
    nlohmann::ordered_json root;
    if (lowerExtension(source) == ".json") {
        const std::string text = readSceneFile(source);
        try {
            root = nlohmann::ordered_json::parse(text);
        } catch (const nlohmann::json::exception& e) {
            throw SceneError(source.string(), 0, e.what());
        }
        if (root.contains("meshes") && root["meshes"].is_array())
            for (auto& mesh : root["meshes"])
                if (mesh.is_object() && mesh.contains("file") && mesh["file"].is_string()) {
                    const fs::path file = mesh["file"].get<std::string>();
                    mesh["file"] = rebased(file.is_absolute() ? file : sourceDir / file);
                }
    } else {
        root["comment"] = "The view of " + source.filename().string() + " saved by the viewer.";
        root["meshes"] = nlohmann::ordered_json::array({{{"file", rebased(fs::absolute(source))}}});
    }
    if (defaultLight != nullptr) {
        // The scene has no light of its own, so "area_lights" is absent or empty.
        if (!root.contains("area_lights") || !root["area_lights"].is_array())
            root["area_lights"] = nlohmann::ordered_json::array();
        nlohmann::ordered_json vertices = nlohmann::ordered_json::array();
        for (const Vec3& c : defaultLight->corners) vertices.push_back({c.x, c.y, c.z});
        root["area_lights"].push_back(
            {{"comment", "penumbra's default light: the scene has no light of its own (up " +
                             defaultLight->upName() + ")"},
             {"vertices", vertices},
             {"emission", defaultLight->emission},
             {"kd", 0}});
    }
    if (!movedLights.empty()) {
        nlohmann::ordered_json kept = nlohmann::ordered_json::array();
        if (root.contains("moved_lights") && root["moved_lights"].is_array())
            for (const auto& entry : root["moved_lights"]) {
                bool replaced = false;
                for (const PlacedLight& m : movedLights)
                    replaced = replaced || (entry.is_object() && entry.contains("light") &&
                                            entry["light"] == m.light);
                if (!replaced) kept.push_back(entry);
            }
        for (const PlacedLight& m : movedLights) {
            nlohmann::ordered_json vertices = nlohmann::ordered_json::array();
            for (const Vec3& v : m.vertices) vertices.push_back({v.x, v.y, v.z});
            kept.push_back({{"comment", "moved in the viewer"},
                            {"light", m.light},
                            {"vertices", std::move(vertices)}});
        }
        root["moved_lights"] = std::move(kept);
    }
    root["camera"] = {{"eye", {camera.eye.x, camera.eye.y, camera.eye.z}},
                      {"target", {camera.target.x, camera.target.y, camera.target.z}},
                      {"up", {camera.up.x, camera.up.y, camera.up.z}},
                      {"fov_y", camera.fovYDegrees}};
    return root.dump(2) + "\n";
}

}  // namespace penumbra
