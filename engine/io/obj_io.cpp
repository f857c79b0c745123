#include "engine/io/obj_io.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <system_error>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/io/atomic_file.h"
#include "engine/io/text_input.h"
#include "engine/io/texture_io.h"
#include "engine/scene/face_check.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// ---- text helpers -------------------------------------------------------------------------------

// A blank inside a line (LineReader has split the lines, so no CR or LF is left in one).
bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

std::string_view stripComment(std::string_view s) {
    const size_t hash = s.find('#');
    return hash == std::string_view::npos ? s : s.substr(0, hash);
}

// Whitespace-separated tokens of one line.
class Tokens {
  public:
    explicit Tokens(std::string_view s) : rest_(s) {}
    bool next(std::string_view& token) {
        rest_ = trim(rest_);
        if (rest_.empty()) return false;
        size_t end = 0;
        while (end < rest_.size() && !isBlank(rest_[end])) ++end;
        token = rest_.substr(0, end);
        rest_.remove_prefix(end);
        return true;
    }
    std::string_view rest() const { return trim(rest_); }

  private:
    std::string_view rest_;
};

// A place in a file, to throw from.
struct Where {
    const std::string& file;
    int64_t line;
    [[noreturn]] void fail(std::string_view message) const {
        throw makeSceneError(file, line, message);
    }
};

// ---- lines --------------------------------------------------------------------------------------

// Splits text into logical lines: LF, CRLF and CR end a line; a line ending in a backslash (and
// without a comment) continues on the next one. Rejects control bytes other than tab, VT and FF
// (binary data).
class LineReader {
  public:
    // Rejects binary data up front, so that a binary file is reported as such rather than by
    // whatever its first bytes happen to look like.
    LineReader(std::string_view text, const std::string& file) : text_(text) {
        if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
        int64_t line = 1;
        size_t lineStart = 0;
        for (size_t i = 0; i < text_.size(); ++i) {
            const auto c = static_cast<unsigned char>(text_[i]);
            if (c == '\n' || c == '\r') {
                if (c == '\r' && i + 1 < text_.size() && text_[i + 1] == '\n') ++i;
                ++line;
                lineStart = i + 1;
            } else if ((c < 0x20 && c != '\t' && c != '\v' && c != '\f') || c == 0x7f) {
                char buf[80];
                std::snprintf(buf, sizeof buf,
                              "binary data (byte 0x%02x at column %zu); not a text file", c,
                              i - lineStart + 1);
                throw makeSceneError(file, line, buf);
            }
        }
    }

    // Advances to the next logical line; false at the end of the text.
    bool next() {
        if (pos_ >= text_.size()) return false;
        lineNumber_ = physicalLine_ + 1;
        joined_.clear();
        bool continued = false;
        while (true) {
            std::string_view physical = readPhysical();
            // A backslash inside a comment ("# C:\\dir\\") continues nothing.
            const bool hasComment = physical.find('#') != std::string_view::npos;
            if (!hasComment && !physical.empty() && physical.back() == '\\') {
                joined_.append(physical.substr(0, physical.size() - 1));
                joined_ += ' ';
                continued = true;
                if (pos_ < text_.size()) continue;
                current_ = joined_;
                return true;
            }
            if (continued) {
                joined_.append(physical);
                current_ = joined_;
            } else {
                current_ = physical;
            }
            return true;
        }
    }

    std::string_view line() const { return current_; }
    int64_t lineNumber() const { return lineNumber_; }

  private:
    std::string_view readPhysical() {
        ++physicalLine_;
        const size_t start = pos_;
        size_t end = start;
        while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
        pos_ = end;
        if (pos_ < text_.size()) {
            if (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ++pos_;
            ++pos_;
        }
        return text_.substr(start, end - start);
    }

    std::string_view text_;
    size_t pos_ = 0;
    int64_t physicalLine_ = 0;
    int64_t lineNumber_ = 0;
    std::string_view current_;
    std::string joined_;
};

// ---- numbers ------------------------------------------------------------------------------------

// The whole token as a finite double (text_input's rules), or an error naming what it was for.
double numberOrFail(std::string_view token, const Where& where, std::string_view what) {
    NumberFault fault{};
    if (const std::optional<double> value = parseFinite(token, &fault)) return *value;
    if (fault == NumberFault::kOutOfRange) {
        where.fail(std::string(what) + ": number " + quoteForMessage(token) +
                   " out of range for a double");
    }
    if (fault == NumberFault::kNotFinite) {
        where.fail(std::string(what) + ": non-finite number " + quoteForMessage(token) +
                   " (NaN and infinity are not allowed)");
    }
    where.fail(std::string(what) + ": malformed number " + quoteForMessage(token));
}

std::string fmt17(double x) {
    // Same digits as printf("%.17g"), but independent of the C locale.
    char buf[40];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 17);
    return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

// ---- files --------------------------------------------------------------------------------------

// ---- MTL ----------------------------------------------------------------------------------------

struct MaterialTable {
    std::vector<Material> materials;
    std::unordered_map<std::string, int32_t> byName;
    std::vector<TextureImage> textures;                      // the map_Kd images, decoded
    std::unordered_map<std::string, int32_t> textureByPath;  // each file decoded once
};

// A repair seen while reading one file: the first occurrence and how many there were.
struct Repair {
    int64_t line = 0;
    std::string what;  // the first occurrence, as its message
    size_t count = 0;
    void note(int64_t at, std::string message) {
        if (count++ == 0) {
            line = at;
            what = std::move(message);
        }
    }
};

Vec3 parseColor(Tokens& tokens, const Where& where, std::string_view key) {
    std::vector<std::string_view> parts;
    std::string_view token;
    while (tokens.next(token)) parts.push_back(token);
    if (!parts.empty() &&
        (equalsIgnoreCase(parts[0], "spectral") || equalsIgnoreCase(parts[0], "xyz"))) {
        where.fail(std::string(key) + ": " + std::string(parts[0]) +
                   " colours are not supported (give r g b)");
    }
    if (parts.size() != 1 && parts.size() != 3) {
        where.fail(std::string(key) + ": expected 1 or 3 numbers, got " +
                   std::to_string(parts.size()));
    }
    double c[3];
    for (size_t i = 0; i < 3; ++i) {
        const std::string_view part = parts[parts.size() == 1 ? 0 : i];
        c[i] = numberOrFail(part, where, key);
        if (c[i] < 0) where.fail(std::string(key) + ": negative value " + quoteForMessage(part));
    }
    return {c[0], c[1], c[2]};
}

// A map_Kd statement: its options, then the image file (the rest of the line, spaces and all).
// -o and -s (1 to 3 numbers: u, v, w) offset and scale the texture coordinates, -clamp on|off
// clamps them; the other options of the MTL format are skipped with their arguments (they change
// nothing a base colour needs). What cannot be used (an unknown option, a missing or malformed
// argument, no file name) is `problem`, reported as an unusable texture (never a parse error: a
// texture is never needed to load the geometry).
struct MapKd {
    std::string file;
    Uv offset{0, 0}, scale{1, 1};
    bool clamp = false;
    std::string problem;
};

MapKd parseMapKd(Tokens tokens) {
    MapKd map;
    const auto isNumber = [](std::string_view t) { return parseFinite(t).has_value(); };
    const auto refuse = [&map](std::string problem) {
        map.problem = std::move(problem);
        return map;
    };
    while (true) {
        Tokens peek = tokens;
        std::string_view option;
        if (!peek.next(option) || option.size() < 2 || option[0] != '-' || isNumber(option)) break;
        tokens = peek;
        const std::string name(option);
        std::string_view arg;
        if (name == "-o" || name == "-s" || name == "-t") {
            double v[3] = {0, 0, 0};
            size_t n = 0;
            while (n < 3) {
                Tokens next = tokens;
                if (!next.next(arg) || !isNumber(arg)) break;
                v[n++] = *parseFinite(arg);
                tokens = next;
            }
            if (n == 0) return refuse("option " + name + " needs 1 to 3 numbers");
            if (name == "-o") map.offset = {v[0], n > 1 ? v[1] : 0};
            if (name == "-s") map.scale = {v[0], n > 1 ? v[1] : 1};
            continue;
        }
        // The options with one word (on/off, a name, a number) or two numbers.
        size_t words = 0;
        for (const char* o : {"-blendu", "-blendv", "-cc", "-clamp", "-imfchan", "-type", "-bm",
                              "-boost", "-texres"})
            if (name == o) words = 1;
        if (name == "-mm") words = 2;
        if (words == 0) return refuse("unknown option " + quoteForMessage(name));
        for (size_t k = 0; k < words; ++k)
            if (!tokens.next(arg)) return refuse("option " + name + " without its argument");
        if (name == "-clamp") {
            if (!equalsIgnoreCase(arg, "on") && !equalsIgnoreCase(arg, "off"))
                return refuse("-clamp must be on or off, not " + quoteForMessage(arg));
            map.clamp = equalsIgnoreCase(arg, "on");
        }
    }
    map.file = std::string(tokens.rest());
    if (map.file.empty()) return refuse("no file name");
    return map;
}

// Reads one MTL library into `table`. A newmtl without a name is an error when `strict`; otherwise
// that material (its statements up to the next newmtl) is ignored and one line per file is added to
// `warnings`. A map_Kd whose image cannot be used (unreadable, undecodable, an unknown option) is
// an error when `strict`; otherwise its material keeps Kd alone and one line per file is added to
// `warnings`. Images resolve against the library's directory.
void parseMtl(std::string_view text, const std::string& file, MaterialTable& table, bool strict,
              std::vector<std::string>& warnings) {
    LineReader lines(text, file);
    constexpr int32_t kNone = -1, kUnnamed = -2;
    int32_t current = kNone;
    Repair unnamed, unusableMap;
    while (lines.next()) {
        const Where where{file, lines.lineNumber()};
        const std::string_view content = stripComment(lines.line());
        Tokens tokens(content);
        std::string_view key;
        if (!tokens.next(key)) continue;
        if (equalsIgnoreCase(key, "newmtl")) {
            const std::string name(tokens.rest());
            if (name.empty()) {
                if (strict) where.fail("newmtl without a material name");
                unnamed.note(where.line, "");
                current = kUnnamed;
                continue;
            }
            if (table.byName.count(name))
                where.fail("material " + quoteForMessage(name) + " defined twice");
            if (table.materials.size() >= kMaxSceneElements) where.fail("too many materials");
            current = static_cast<int32_t>(table.materials.size());
            table.byName.emplace(name, current);
            Material m;
            m.name = name;
            table.materials.push_back(std::move(m));
            continue;
        }
        const bool isKd = equalsIgnoreCase(key, "Kd"), isKs = equalsIgnoreCase(key, "Ks"),
                   isKe = equalsIgnoreCase(key, "Ke"), isNs = equalsIgnoreCase(key, "Ns"),
                   isMapKd = equalsIgnoreCase(key, "map_Kd");
        if (!isKd && !isKs && !isKe && !isNs && !isMapKd)
            continue;  // Ka, Ni, d, Tr, illum, the other map_*, ...
        if (current == kNone) where.fail(quoteForMessage(key) + " before any newmtl");
        if (current == kUnnamed) continue;  // the unnamed material's, ignored with it
        Material& m = table.materials[static_cast<size_t>(current)];
        if (isMapKd) {
            const MapKd map = parseMapKd(tokens);
            const fs::path path = fs::path(file).parent_path() / fs::path(map.file);
            std::string problem = map.problem;
            int32_t image = -1;
            if (problem.empty()) {
                const std::string key = path.lexically_normal().string();
                const auto cached = table.textureByPath.find(key);
                if (cached != table.textureByPath.end()) {
                    image = cached->second;
                } else {
                    TextureRead read = readTextureFile(path);
                    if (read.image) {
                        image = static_cast<int32_t>(table.textures.size());
                        table.textures.push_back(std::move(*read.image));
                        table.textureByPath.emplace(key, image);
                    } else {
                        problem = read.problem;
                    }
                }
            }
            if (image < 0) {
                const std::string what =
                    "map_Kd " +
                    (map.file.empty() ? std::string()
                                      : quoteForMessage(map.file) + " (" + path.string() + ") ") +
                    "of material " + quoteForMessage(m.name) + ": " + problem;
                if (strict) where.fail(what);
                unusableMap.note(where.line, what);
                m.kdMap = {};
                continue;
            }
            m.kdMap = {};
            m.kdMap.image = image;
            if (map.clamp) m.kdMap.wrapU = m.kdMap.wrapV = TextureWrap::ClampToEdge;
            // The MTL's offset and scale act on OBJ's (u, v up); the scene's v runs down
            // (texture.h): v_image = 1 - (s_v (1 - v) + o_v) = s_v v + (1 - s_v - o_v).
            m.kdMap.transform.scale = map.scale;
            m.kdMap.transform.offset = {map.offset.u, 1 - map.scale.v - map.offset.v};
            continue;
        }
        if (isNs) {
            std::string_view value;
            if (!tokens.next(value)) where.fail("Ns: missing value");
            m.ns = numberOrFail(value, where, "Ns");
            if (m.ns < 0) where.fail("Ns: negative value " + quoteForMessage(value));
            std::string_view extra;
            if (tokens.next(extra)) where.fail("Ns: unexpected " + quoteForMessage(extra));
        } else {
            (isKd ? m.kd : isKs ? m.ks : m.ke) = parseColor(tokens, where, key);
        }
    }
    if (unnamed.count > 0) {
        warnings.push_back(
            file + ": newmtl without a material name on line " + std::to_string(unnamed.line) +
            (unnamed.count > 1 ? " (and " + std::to_string(unnamed.count - 1) + " more)"
                               : std::string()) +
            (unnamed.count > 1 ? ": those materials are ignored, with their statements"
                               : ": that material is ignored, with its statements"));
    }
    if (unusableMap.count > 0) {
        warnings.push_back(file + ":" + std::to_string(unusableMap.line) + ": " + unusableMap.what +
                           (unusableMap.count > 1
                                ? " (and " + std::to_string(unusableMap.count - 1) + " more map_Kd)"
                                : std::string()) +
                           ": the material uses its Kd alone");
    }
}

// ---- OBJ ----------------------------------------------------------------------------------------

bool isIgnoredStatement(std::string_view k) {
    static constexpr std::string_view kIgnored[] = {
        "vn",    "vp",       "o",        "g",      "s",      "l",          "p",         "mg", "lod",
        "bevel", "c_interp", "d_interp", "usemap", "maplib", "shadow_obj", "trace_obj", "csh"};
    return std::find(std::begin(kIgnored), std::end(kIgnored), k) != std::end(kIgnored);
}

bool isFreeFormStatement(std::string_view k) {
    static constexpr std::string_view kFreeForm[] = {
        "cstype", "deg",  "bmat", "step", "curv", "curv2", "surf",  "parm",
        "trim",   "hole", "scrv", "sp",   "end",  "con",   "ctech", "stech"};
    return std::find(std::begin(kFreeForm), std::end(kFreeForm), k) != std::end(kFreeForm);
}

// Where MTL libraries come from: files next to the OBJ, or one text for all of them.
struct MtlSource {
    std::optional<std::string_view> text;  // set: every mtllib reads this text
    fs::path directory;                    // the OBJ's directory (names resolve against it)
};

class ObjParser {
  public:
    ObjParser(const std::string& file, MtlSource mtl, const LoadOptions& options)
        : file_(file), mtl_(std::move(mtl)), options_(options) {}

    Scene parse(std::string_view text) {
        LineReader lines(text, file_);
        while (lines.next()) statement(lines.line(), lines.lineNumber());
        return finish();
    }

  private:
    struct UseMtl {
        std::string name;
        int64_t line;
    };

    void statement(std::string_view raw, int64_t line) {
        const Where where{file_, line};
        const std::string_view content = stripComment(raw);
        Tokens tokens(content);
        std::string_view keyword;
        if (!tokens.next(keyword)) return;
        if (keyword == "v") {
            vertex(tokens, where);
        } else if (keyword == "vt") {
            texCoord(tokens, where);
        } else if (keyword == "f") {
            face(tokens, where);
        } else if (keyword == "usemtl") {
            std::string name(tokens.rest());
            if (name.empty()) where.fail("usemtl without a material name");
            currentUseMtl_ = static_cast<int32_t>(useMtl_.size());
            useMtl_.push_back({std::move(name), line});
        } else if (keyword == "mtllib") {
            mtllib(tokens, where);
        } else if (isIgnoredStatement(keyword)) {
            return;
        } else if (isFreeFormStatement(keyword)) {
            where.fail("free-form geometry (" + quoteForMessage(keyword) +
                       ") is not supported; export polygons");
        } else if (keyword == "call") {
            where.fail("'call' is not supported; merge the files");
        } else {
            where.fail("unknown statement " + quoteForMessage(keyword));
        }
    }

    [[noreturn]] static void failFace(const Where& where, size_t face, std::string_view message) {
        where.fail("face " + std::to_string(face) + ": " + std::string(message));
    }

    void vertex(Tokens& tokens, const Where& where) {
        if (scene_.mesh.vertices.size() >= kMaxSceneElements) {
            where.fail("too many vertices (the limit is 2^30)");
        }
        double c[3] = {0, 0, 0};
        size_t count = 0;
        std::string_view token;
        while (tokens.next(token)) {
            if (count >= 7) where.fail("vertex: too many numbers (at most x y z w r g b)");
            static constexpr std::string_view kWhat[] = {
                "vertex coordinate 1", "vertex coordinate 2", "vertex coordinate 3", "vertex w",
                "vertex colour 1",     "vertex colour 2",     "vertex colour 3"};
            const double value = numberOrFail(token, where, kWhat[count]);
            if (count < 3) c[count] = value;
            ++count;
        }
        if (count < 3) {
            where.fail("vertex: too few coordinates (need 3, got " + std::to_string(count) + ")");
        }
        scene_.mesh.vertices.push_back({c[0], c[1], c[2]});
    }

    // vt u [v [w]]: kept as (u, 1 - v), v down as the scene's coordinates run (texture.h).
    void texCoord(Tokens& tokens, const Where& where) {
        if (texCoords_.size() >= kMaxSceneElements)
            where.fail("too many texture coordinates (the limit is 2^30)");
        double c[2] = {0, 0};
        size_t count = 0;
        std::string_view token;
        while (tokens.next(token)) {
            if (count >= 3) where.fail("vt: too many numbers (at most u v w)");
            const double value = numberOrFail(token, where, "texture coordinate");
            if (count < 2) c[count] = value;
            ++count;
        }
        if (count == 0) where.fail("vt: no coordinates");
        texCoords_.push_back({c[0], 1 - c[1]});
    }

    // A face corner's texture coordinate: its 0-based vt index, or kNoVt.
    static constexpr uint32_t kNoVt = UINT32_MAX;

    // One `v`, `v/vt`, `v//vn` or `v/vt/vn` reference; returns the 0-based vertex index, which for
    // a positive index may still be out of range (checked at the end, against the whole file), and
    // in `vt` the 0-based texture coordinate index (the same rules), or kNoVt.
    uint32_t faceVertex(std::string_view token, const Where& where, size_t faceIndex,
                        uint32_t& vt) {
        const auto fail = [&](std::string_view message) { failFace(where, faceIndex, message); };
        const auto malformed = [&] {
            fail("malformed vertex reference " + quoteForMessage(token) +
                 " (expected v, v/vt, v//vn or v/vt/vn)");
        };
        std::string_view parts[3];
        size_t count = 0;
        for (std::string_view rest = token;;) {
            if (count == 3) malformed();
            const size_t slash = rest.find('/');
            parts[count++] = rest.substr(0, slash);
            if (slash == std::string_view::npos) break;
            rest.remove_prefix(slash + 1);
        }
        // v: parts[0]; v/vt: vt nonempty; v//vn and v/vt/vn: vn nonempty, vt may be empty.
        if (parts[0].empty()) malformed();
        if (count == 2 && parts[1].empty()) malformed();
        if (count == 3 && parts[2].empty()) malformed();
        vt = kNoVt;
        for (size_t i = 1; i < count; ++i) {
            if (parts[i].empty()) continue;
            const std::optional<int64_t> other = parseInteger(parts[i]);
            if (!other) malformed();
            if (*other == 0) {
                fail(std::string(i == 1 ? "texture" : "normal") +
                     " index 0 is invalid (OBJ indices start at 1)");
            }
            if (i != 1) continue;
            const auto defined = static_cast<int64_t>(texCoords_.size());
            if (*other < 0) {
                if (*other < -defined)
                    fail("texture index " + std::to_string(*other) + " out of range (only " +
                         std::to_string(defined) +
                         " texture coordinates defined before this line)");
                vt = static_cast<uint32_t>(defined + *other);
            } else {
                if (*other > static_cast<int64_t>(kMaxSceneElements))
                    fail("texture index " + std::to_string(*other) +
                         " out of range (more than the 2^30 limit)");
                vt = static_cast<uint32_t>(*other - 1);
            }
        }
        NumberFault fault{};
        const std::optional<int64_t> index = parseInteger(parts[0], {}, &fault);
        if (!index) {
            if (fault == NumberFault::kOutOfRange)
                fail("vertex index " + quoteForMessage(parts[0]) + " out of range");
            malformed();
        }
        const int64_t i = *index;
        const auto defined = static_cast<int64_t>(scene_.mesh.vertices.size());
        if (i == 0) fail("vertex index 0 is invalid (OBJ indices start at 1)");
        if (i < 0) {
            if (i < -defined) {
                fail("vertex index " + std::to_string(i) + " out of range (only " +
                     std::to_string(defined) + " vertices defined before this line)");
            }
            return static_cast<uint32_t>(defined + i);
        }
        if (i > static_cast<int64_t>(kMaxSceneElements)) {
            fail("vertex index " + std::to_string(i) +
                 " out of range (more than the 2^30 vertex limit)");
        }
        return static_cast<uint32_t>(i - 1);
    }

    void face(Tokens& tokens, const Where& where) {
        const size_t faceIndex = scene_.mesh.faces.size();
        if (faceIndex >= kMaxSceneElements) where.fail("too many faces (the limit is 2^30)");
        std::vector<uint32_t> indices;
        std::vector<uint32_t>& vts = vtScratch_;
        vts.clear();
        std::string_view token;
        bool allVt = true;
        uint32_t maxVt = 0;  // the largest vt index, 1-based (0: none)
        while (tokens.next(token)) {
            uint32_t vt = kNoVt;
            indices.push_back(faceVertex(token, where, faceIndex, vt));
            vts.push_back(vt);
            allVt = allVt && vt != kNoVt;
            if (vt != kNoVt) maxVt = std::max(maxVt, vt + 1);
        }
        if (indices.size() < 3) {
            failFace(where, faceIndex,
                     "too few vertices (" + std::to_string(indices.size()) +
                         "; a face needs at least 3)");
        }
        std::vector<uint32_t>& sorted = sortedScratch_;
        sorted.assign(indices.begin(), indices.end());
        std::sort(sorted.begin(), sorted.end());
        const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
        // Under kDrop a repeated vertex is a degenerate face for checkLoadedFaces to drop.
        if (dup != sorted.end() && options_.faces == DegenerateFaces::kReject) {
            failFace(where, faceIndex,
                     "vertex " + std::to_string(*dup + 1ull) + " repeated (degenerate face)");
        }
        // Its largest vt index (checked against the whole file in finish()), and its vt indices
        // when every corner has one (its texture coordinates).
        if (maxVt > 0) {
            faceMaxVt_.resize(faceIndex);
            faceMaxVt_.push_back(maxVt);
        }
        if (allVt) {
            faceVt_.resize(faceIndex);
            faceVt_.push_back(vts);
        }
        scene_.mesh.faces.push_back(std::move(indices));
        scene_.faceSourceLine.push_back(
            static_cast<int32_t>(std::min<int64_t>(where.line, INT32_MAX)));
        faceUseMtl_.push_back(currentUseMtl_);
    }

    void mtllib(Tokens& tokens, const Where& where) {
        const std::string_view whole = tokens.rest();
        if (whole.empty()) where.fail("mtllib without a file name");
        if (mtl_.text) {
            // Every library is the one given text, read once.
            if (!mtlTextRead_) {
                mtlTextRead_ = true;
                const std::string name = (mtl_.directory / fs::path(std::string(whole))).string();
                parseMtl(*mtl_.text, name, table_, options_.strict, scene_.warnings);
            }
            return;
        }
        // The whole rest of the line when it names a file (names with spaces), else each name.
        std::vector<std::string> names;
        std::error_code ec;
        if (fs::is_regular_file(mtl_.directory / fs::path(std::string(whole)), ec)) {
            names.emplace_back(whole);
        } else {
            std::string_view name;
            while (tokens.next(name)) names.emplace_back(name);
        }
        for (const std::string& name : names) {
            const fs::path path = mtl_.directory / fs::path(name);
            const std::string key = path.lexically_normal().string();
            if (!mtlFilesRead_.insert(key).second) continue;
            std::string text;
            try {
                text = readWholeFile(path);
            } catch (const FileReadError& e) {
                const std::string message = "cannot read material library " +
                                            quoteForMessage(name) + " (" + path.string() +
                                            "): " + e.reason;
                if (options_.strict) where.fail("mtllib: " + message);
                unreadableMtl_.note(where.line, message);
                continue;
            }
            parseMtl(text, path.string(), table_, options_.strict, scene_.warnings);
        }
    }

    Scene finish() {
        // Deferred checks: positive indices against the whole file, usemtl names against all
        // libraries. The earliest line wins.
        FirstError first = indexOutOfRange();
        // Why a usemtl can name no material: "no mtllib" or the count of those defined.
        const bool noMtllib = mtlFilesRead_.empty() && !mtlTextRead_ && unreadableMtl_.count == 0;
        const std::string context =
            noMtllib ? "no mtllib"
                     : std::to_string(table_.materials.size()) + " materials defined" +
                           (unreadableMtl_.count > 0 ? ", a material library unreadable" : "");
        Repair unknown;
        const size_t knownMaterials = table_.materials.size();
        const std::vector<int32_t> useMtlMaterial = useMtlMaterials(first, unknown, noMtllib);
        if (first.line != INT64_MAX) throw makeSceneError(file_, first.line, first.message);
        if (scene_.mesh.faces.empty()) throw makeSceneError(file_, 0, "no faces");

        scene_.sourcePath = file_;
        scene_.materials = std::move(table_.materials);
        scene_.textures = std::move(table_.textures);
        scene_.faceMaterial.reserve(faceUseMtl_.size());
        for (int32_t u : faceUseMtl_) {
            scene_.faceMaterial.push_back(u < 0 ? -1 : useMtlMaterial[static_cast<size_t>(u)]);
        }
        resolveTexCoords();
        // One warning line per kind, the material ones before the faces': the MTL files' own
        // (newmtl without a name) came first; the default material's faces are counted in the
        // repaired mesh.
        if (unreadableMtl_.count > 0) {
            scene_.warnings.push_back(
                file_ + ":" + std::to_string(unreadableMtl_.line) +
                ": mtllib: " + unreadableMtl_.what +
                (unreadableMtl_.count > 1
                     ? " (and " + std::to_string(unreadableMtl_.count - 1) + " more libraries)"
                     : std::string()) +
                "; its materials are missing");
        }
        const size_t unknownWarning = scene_.warnings.size();
        checkLoadedFaces(scene_, options_.faces);
        if (unknown.count > 0)
            warnUnknownMaterials(unknown, unknownWarning, knownMaterials, context);
        return std::move(scene_);
    }

    // Scene::faceUv from the faces' vt indices (in range: indexOutOfRange checked them); faces of
    // a textured material without them counted for one warning (strict: an error).
    void resolveTexCoords() {
        const size_t nf = scene_.mesh.faces.size();
        if (!faceVt_.empty()) {
            faceVt_.resize(nf);
            scene_.faceUv.resize(nf);
            for (size_t f = 0; f < nf; ++f)
                for (uint32_t vt : faceVt_[f]) scene_.faceUv[f].push_back(texCoords_.at(vt));
        }
        size_t without = 0;
        int64_t firstLine = 0;
        for (size_t f = 0; f < nf; ++f) {
            if (!scene_.material(static_cast<uint32_t>(f)).kdMap.present()) continue;
            if (f < scene_.faceUv.size() && !scene_.faceUv[f].empty()) continue;
            if (without++ == 0) firstLine = scene_.faceSourceLine[f];
        }
        if (without == 0) return;
        const std::string what = std::to_string(without) +
                                 " faces of a material with a map_Kd have no texture coordinates "
                                 "(vt), the first on line " +
                                 std::to_string(firstLine);
        if (options_.strict) throw makeSceneError(file_, firstLine, what);
        scene_.warnings.push_back(file_ + ": " + what + ": they use the material's Kd alone");
    }

    // The earliest deferred error: its line (INT64_MAX: none) and message.
    struct FirstError {
        int64_t line = INT64_MAX;
        std::string message;
    };

    // The first face with a positive vertex or texture index beyond the whole file's vertices or
    // texture coordinates.
    FirstError indexOutOfRange() const {
        const size_t nv = scene_.mesh.vertices.size();
        for (size_t f = 0; f < scene_.mesh.faces.size(); ++f) {
            for (uint32_t i : scene_.mesh.faces[f]) {
                if (i >= nv) {
                    return {scene_.faceSourceLine[f],
                            "face " + std::to_string(f) + ": vertex index " +
                                std::to_string(i + 1ull) + " out of range (file has " +
                                std::to_string(nv) + " vertices)"};
                }
            }
            if (f < faceMaxVt_.size() && faceMaxVt_[f] > texCoords_.size()) {
                return {scene_.faceSourceLine[f],
                        "face " + std::to_string(f) + ": texture index " +
                            std::to_string(faceMaxVt_[f]) + " out of range (file has " +
                            std::to_string(texCoords_.size()) + " texture coordinates)"};
            }
        }
        return {};
    }

    // Each usemtl's material: the libraries'; for a name they lack, an error (strict: `first`,
    // when earlier) or a default material under that name, one per name, after the libraries'
    // (so a JSON scene can still give it colours by name), noted in `unknown`.
    std::vector<int32_t> useMtlMaterials(FirstError& first, Repair& unknown, bool noMtllib) {
        std::vector<int32_t> useMtlMaterial(useMtl_.size(), -1);
        const size_t knownMaterials = table_.materials.size();
        for (size_t u = 0; u < useMtl_.size(); ++u) {
            const auto it = table_.byName.find(useMtl_[u].name);
            if (it != table_.byName.end() && static_cast<size_t>(it->second) < knownMaterials) {
                useMtlMaterial[u] = it->second;
                continue;
            }
            if (options_.strict) {
                if (useMtl_[u].line < first.line) {
                    first.line = useMtl_[u].line;
                    first.message = "usemtl: unknown material " + quoteForMessage(useMtl_[u].name) +
                                    " (" + std::to_string(table_.materials.size()) +
                                    " materials defined" + (noMtllib ? ", no mtllib" : "") + ")";
                }
                continue;
            }
            unknown.note(useMtl_[u].line, quoteForMessage(useMtl_[u].name) + " on line " +
                                              std::to_string(useMtl_[u].line));
            if (it != table_.byName.end()) {
                useMtlMaterial[u] = it->second;
                continue;
            }
            if (table_.materials.size() >= kMaxSceneElements) {
                throw makeSceneError(file_, useMtl_[u].line, "too many materials");
            }
            const auto index = static_cast<int32_t>(table_.materials.size());
            table_.byName.emplace(useMtl_[u].name, index);
            Material m;
            m.name = useMtl_[u].name;
            table_.materials.push_back(std::move(m));
            useMtlMaterial[u] = index;
        }
        return useMtlMaterial;
    }

    // The warning for the usemtl names without a material, at warnings[at] (before the faces'),
    // with the faces that took a default material (those of materials past knownMaterials).
    void warnUnknownMaterials(const Repair& unknown, size_t at, size_t knownMaterials,
                              const std::string& context) {
        const auto defaultFaces = static_cast<size_t>(std::count_if(
            scene_.faceMaterial.begin(), scene_.faceMaterial.end(),
            [&](int32_t m) { return m >= 0 && static_cast<size_t>(m) >= knownMaterials; }));
        const std::string faces =
            std::to_string(defaultFaces) + (defaultFaces == 1 ? " face uses" : " faces use");
        scene_.warnings.insert(
            scene_.warnings.begin() + static_cast<std::ptrdiff_t>(at),
            file_ + ": " +
                (unknown.count == 1
                     ? "usemtl " + unknown.what + " names no material (" + context + ")"
                     : std::to_string(unknown.count) + " usemtl lines name no material (first: " +
                           unknown.what + "; " + context + ")") +
                ": " + faces + " a default diffuse material");
    }

    const std::string& file_;
    MtlSource mtl_;
    LoadOptions options_;
    Scene scene_;
    MaterialTable table_;
    std::vector<UseMtl> useMtl_;
    std::vector<int32_t> faceUseMtl_;  // per face, index into useMtl_ or -1
    int32_t currentUseMtl_ = -1;
    std::unordered_set<std::string> mtlFilesRead_;
    bool mtlTextRead_ = false;
    Repair unreadableMtl_;  // mtllib lines whose library cannot be read (repair mode)
    std::vector<uint32_t> sortedScratch_, vtScratch_;
    std::vector<Uv> texCoords_;                  // the vt lines, v flipped
    std::vector<std::vector<uint32_t>> faceVt_;  // per face its vt indices (empty: none), or empty
    std::vector<uint32_t> faceMaxVt_;  // per face its largest vt index, 1-based (0: none), or empty
};

// ---- writing ------------------------------------------------------------------------------------

bool writableName(std::string_view name) {
    if (name.empty() || name != trim(name)) return false;
    for (char ch : name) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x20 || c == 0x7f || c == '#' || c == '\\') return false;
    }
    return true;
}

// Writes `text` to `target` atomically (engine/io/atomic_file.h); a failure is a SceneError
// naming the file.
void writeAtomically(const fs::path& target, const std::string& text) {
    try {
        writeFileAtomically(target, text);
    } catch (const AtomicWriteError& e) {
        throw makeSceneError(target.string(), 0, e.what());
    }
}

}  // namespace

Scene loadObj(const std::filesystem::path& objPath, const LoadOptions& options) {
    const std::string file = objPath.string();
    const std::string text = readSceneFile(objPath);
    ObjParser parser(file, MtlSource{std::nullopt, objPath.parent_path()}, options);
    return parser.parse(text);
}

Scene loadObjFromString(std::string_view objText, std::string_view mtlText, std::string sourceName,
                        const LoadOptions& options) {
    ObjParser parser(sourceName, MtlSource{mtlText, fs::path(sourceName).parent_path()}, options);
    return parser.parse(objText);
}

void writeObj(const Scene& scene, const std::filesystem::path& objPath) {
    const std::string objFile = objPath.string();
    if (!objPath.has_filename()) throw makeSceneError(objFile, 0, "cannot write: not a file name");
    fs::path mtlPath = objPath;
    mtlPath.replace_extension(".mtl");
    if (mtlPath == objPath) {
        throw makeSceneError(objFile, 0, "cannot write: the OBJ file must not be named *.mtl");
    }
    const std::string mtlName = mtlPath.filename().string();
    if (!writableName(mtlName)) {
        throw makeSceneError(objFile, 0,
                             "cannot write: material library name " + quoteForMessage(mtlName) +
                                 " cannot be written in an OBJ file");
    }
    validateScene(scene);

    // Material names: writable and unique; a name for the default material when one is needed.
    std::unordered_set<std::string> names;
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const std::string& name = scene.materials[m].name;
        if (!writableName(name) || !names.insert(name).second) {
            throw makeSceneError(objFile, 0,
                                 "cannot write: material " + std::to_string(m) + " name " +
                                     quoteForMessage(name) +
                                     " is empty, repeated or not writable in MTL");
        }
    }
    bool needDefault = false;
    for (size_t f = 0, seenMaterial = 0; f < scene.faceMaterial.size(); ++f) {
        if (scene.faceMaterial[f] >= 0) seenMaterial = 1;
        if (scene.faceMaterial[f] < 0 && seenMaterial) needDefault = true;
    }
    std::string defaultName = "penumbra_default";
    for (int n = 1; names.count(defaultName); ++n)
        defaultName = "penumbra_default_" + std::to_string(n);

    std::string mtl = "# penumbra scene v1\n";
    const auto writeMaterial = [&mtl](const Material& m) {
        const auto color = [](const Vec3& c) {
            return fmt17(c.x) + " " + fmt17(c.y) + " " + fmt17(c.z);
        };
        mtl += "\nnewmtl " + m.name + "\n";
        mtl += "Kd " + color(m.kd) + "\n";
        mtl += "Ks " + color(m.ks) + "\n";
        mtl += "Ke " + color(m.ke) + "\n";
        mtl += "Ns " + fmt17(m.ns) + "\n";
    };
    for (const Material& m : scene.materials) writeMaterial(m);
    if (needDefault) {
        Material m;
        m.name = defaultName;
        writeMaterial(m);
    }

    const vis::PolygonMesh& mesh = scene.mesh;
    std::string obj = "# penumbra scene v1\n";
    obj += "# " + std::to_string(mesh.vertices.size()) + " vertices, " +
           std::to_string(mesh.faces.size()) + " faces, " + std::to_string(scene.lights.size()) +
           " lights\n";
    obj += "mtllib " + mtlName + "\n";
    for (const Vec3& v : mesh.vertices) {
        obj += "v " + fmt17(v.x) + " " + fmt17(v.y) + " " + fmt17(v.z) + "\n";
    }
    int32_t current = -1;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const int32_t m = f < scene.faceMaterial.size() ? scene.faceMaterial[f] : -1;
        if (m != current) {
            obj += "usemtl " +
                   (m >= 0 ? scene.materials[static_cast<size_t>(m)].name : defaultName) + "\n";
            current = m;
        }
        obj += "f";
        for (uint32_t i : mesh.faces[f]) obj += " " + std::to_string(i + 1ull);
        obj += "\n";
    }

    writeAtomically(mtlPath, mtl);
    writeAtomically(objPath, obj);
}

}  // namespace penumbra
