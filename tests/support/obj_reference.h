// An independent reading of OBJ and MTL text, for the OBJ loader's robustness tests: written from
// the formats (Wavefront's OBJ and MTL, restricted to what penumbra reads), not from
// engine/io/obj_io.cpp, it says what loading a text must give: refused at a line of a file, or
// these vertices, faces and area lights. Its rules:
//   - lines end at LF, CR or CRLF; a line ending in a backslash (and without a '#') continues on
//     the next, and the joined line is reported at its first line; '#' starts a comment; tokens
//     are separated by space, tab, VT and FF;
//   - a control byte other than tab, VT and FF (or DEL) anywhere: not a text file, refused at its
//     line before anything else is read;
//   - numbers: [+-]digits[.digits][(e|E)[+-]digits] (digits on at least one side of the point)
//     whose value is a finite double (strtod, no range error);
//   - OBJ: `v` with 3 to 7 numbers (x y z [w [r g b]]); `vt` with 1 to 3 numbers (u [v [w]]);
//     `f` with at least 3 references v, v/vt, v//vn or v/vt/vn of nonzero integers (vn checked
//     for form only: penumbra reads no normals), a negative v or vt counting back from the
//     vertices or texture coordinates defined before the line, a positive one checked against the
//     whole file once it is read (the first such face's line is reported, after every other error
//     of the text);
//     `usemtl NAME`; `mtllib NAME` reads the one library text given (at the first mtllib, named
//     NAME); the statements of the spec that carry nothing a polygon renderer reads (normals,
//     grouping, display attributes) are skipped; any other is refused;
//   - MTL: keys in any case; `newmtl NAME` (a name defined twice is refused; one without a name
//     is skipped with its statements); Kd, Ks, Ke with 1 or 3 non-negative numbers and Ns with
//     one, refused before any newmtl; map_Kd refused before any newmtl, else never (an image
//     that cannot be used is a warning); other keys skipped;
//   - a usemtl naming no material gives the faces a default, non-emissive material; a face is an
//     area light when its material has a positive Ke;
//   - refused at line 0 (the file as a whole): a text without faces, then one with a coordinate
//     beyond the scene contract's magnitude, 2^59 (engine/scene/scene_validation.h).
// Not modelled: repeated vertices in a face and the loader's repairs of faces (degenerate ones
// dropped, non-planar and non-convex ones split): a caller compares faces only where the loader
// reports no repair.
#pragma once

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "visibility/vec3.h"

namespace penumbra::test {

struct ObjReading {
    std::string errorFile;  // empty when the text loads
    int64_t errorLine = 0;
    std::vector<vis::Vec3> vertices;
    std::vector<std::vector<uint32_t>> faces;
    std::vector<uint32_t> lights;  // faces whose material emits, in face order
    bool refused() const { return !errorFile.empty(); }
};

namespace obj_reference {

struct Line {
    int64_t number;
    std::string text;
};

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

inline std::vector<std::string> tokens(std::string_view s) {
    std::vector<std::string> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && isSpace(s[i])) ++i;
        const size_t start = i;
        while (i < s.size() && !isSpace(s[i])) ++i;
        if (i > start) out.emplace_back(s.substr(start, i - start));
    }
    return out;
}

// The line of the first byte that is not text, if any.
inline std::optional<int64_t> binaryByteLine(std::string_view text) {
    int64_t line = 1;
    for (size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') continue;  // CRLF: at LF
        if (c == '\n' || c == '\r') {
            ++line;
        } else if ((c < 0x20 && c != '\t' && c != '\v' && c != '\f') || c == 0x7f) {
            return line;
        }
    }
    return std::nullopt;
}

// Logical lines (continuations joined), comments removed.
inline std::vector<Line> logicalLines(std::string_view text) {
    std::vector<Line> physical;
    for (size_t start = 0; start < text.size();) {
        size_t end = start;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        physical.push_back({static_cast<int64_t>(physical.size()) + 1,
                            std::string(text.substr(start, end - start))});
        start = end;
        if (start < text.size() && text[start] == '\r' && start + 1 < text.size() &&
            text[start + 1] == '\n')
            ++start;
        if (start < text.size()) ++start;
    }
    std::vector<Line> out;
    for (size_t i = 0; i < physical.size(); ++i) {
        Line joined{physical[i].number, ""};
        while (true) {
            const std::string& p = physical[i].text;
            const bool continues =
                p.find('#') == std::string::npos && !p.empty() && p.back() == '\\';
            if (!continues) {
                joined.text += p;
                break;
            }
            joined.text += p.substr(0, p.size() - 1) + " ";
            if (i + 1 == physical.size()) break;
            ++i;
        }
        joined.text = joined.text.substr(0, joined.text.find('#'));
        out.push_back(std::move(joined));
    }
    return out;
}

inline bool isDigit(char c) { return c >= '0' && c <= '9'; }

inline std::optional<double> number(const std::string& s) {
    size_t i = 0, digits = 0;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    for (; i < s.size() && isDigit(s[i]); ++i) ++digits;
    if (i < s.size() && s[i] == '.')
        for (++i; i < s.size() && isDigit(s[i]); ++i) ++digits;
    if (digits == 0) return std::nullopt;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        size_t exponent = 0;
        for (; i < s.size() && isDigit(s[i]); ++i) ++exponent;
        if (exponent == 0) return std::nullopt;
    }
    if (i != s.size()) return std::nullopt;
    errno = 0;
    const double value = std::strtod(s.c_str(), nullptr);
    if (errno == ERANGE || !std::isfinite(value)) return std::nullopt;
    return value;
}

// [+-]digits, within int64.
inline std::optional<int64_t> integer(const std::string& s) {
    size_t i = 0;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (i == s.size()) return std::nullopt;
    for (size_t k = i; k < s.size(); ++k)
        if (!isDigit(s[k])) return std::nullopt;
    errno = 0;
    const long long value = std::strtoll(s.c_str(), nullptr, 10);
    if (errno == ERANGE) return std::nullopt;
    return value;
}

inline bool equalsIgnoreCase(const std::string& a, const char* b) {
    const std::string_view v(b);
    if (a.size() != v.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != v[i]) return false;
    return true;
}

// The rest of a line after its keyword, without the blanks around it.
inline std::string rest(const std::string& line, const std::string& keyword) {
    size_t i = line.find(keyword) + keyword.size();
    while (i < line.size() && isSpace(line[i])) ++i;
    size_t end = line.size();
    while (end > i && isSpace(line[end - 1])) --end;
    return line.substr(i, end - i);
}

struct Material {
    bool emits = false;
};

// Reads an MTL text into `materials`; the line of its first error, if any.
inline std::optional<int64_t> readMtl(std::string_view text,
                                      std::map<std::string, Material>& materials) {
    if (const auto line = binaryByteLine(text)) return line;
    enum { kNone, kUnnamed, kNamed } state = kNone;
    std::string current;
    for (const Line& line : logicalLines(text)) {
        const std::vector<std::string> t = tokens(line.text);
        if (t.empty()) continue;
        if (equalsIgnoreCase(t[0], "newmtl")) {
            const std::string name = rest(line.text, t[0]);
            if (name.empty()) {
                state = kUnnamed;
                continue;
            }
            if (materials.count(name)) return line.number;
            materials[name] = {};
            current = name;
            state = kNamed;
            continue;
        }
        const bool colour = equalsIgnoreCase(t[0], "kd") || equalsIgnoreCase(t[0], "ks") ||
                            equalsIgnoreCase(t[0], "ke");
        const bool map = equalsIgnoreCase(t[0], "map_kd");
        if (!colour && !map && !equalsIgnoreCase(t[0], "ns")) continue;
        if (state == kNone) return line.number;
        if (state == kUnnamed || map) continue;  // skipped with its material; a map never refuses
        if (colour && t.size() != 2 && t.size() != 4) return line.number;
        if (!colour && t.size() != 2) return line.number;
        bool positive = false;
        for (size_t i = 1; i < t.size(); ++i) {
            const std::optional<double> v = number(t[i]);
            if (!v || *v < 0) return line.number;
            positive = positive || *v > 0;
        }
        if (equalsIgnoreCase(t[0], "ke")) materials[current].emits = positive;
    }
    return std::nullopt;
}

}  // namespace obj_reference

// What loading `obj` (named `objName`, in the current directory) with `mtl` as the text of every
// material library must give.
inline ObjReading readObjReference(std::string_view obj, std::string_view mtl,
                                   const std::string& objName) {
    using namespace obj_reference;
    ObjReading r;
    const auto refuse = [&](const std::string& file, int64_t line) {
        r.errorFile = file;
        r.errorLine = line;
        return r;
    };
    if (const auto line = binaryByteLine(obj)) return refuse(objName, *line);
    static const char* kSkipped[] = {
        "vn",    "vp",       "o",        "g",      "s",      "l",          "p",         "mg", "lod",
        "bevel", "c_interp", "d_interp", "usemap", "maplib", "shadow_obj", "trace_obj", "csh"};
    std::map<std::string, Material> materials;
    bool libraryRead = false;
    std::string useMtl;  // empty: none yet
    std::vector<std::string> faceMaterial;
    std::vector<int64_t> faceLine;
    int64_t texCoords = 0;           // vt lines so far
    std::vector<int64_t> faceMaxVt;  // per face its largest positive vt index (0: none)
    for (const Line& line : logicalLines(obj)) {
        const std::vector<std::string> t = tokens(line.text);
        if (t.empty()) continue;
        const std::string& keyword = t[0];
        if (keyword == "v") {
            if (t.size() < 4 || t.size() > 8) return refuse(objName, line.number);
            double c[3] = {};
            for (size_t i = 1; i < t.size(); ++i) {
                const std::optional<double> v = number(t[i]);
                if (!v) return refuse(objName, line.number);
                if (i <= 3) c[i - 1] = *v;
            }
            r.vertices.push_back({c[0], c[1], c[2]});
        } else if (keyword == "vt") {
            if (t.size() < 2 || t.size() > 4) return refuse(objName, line.number);
            for (size_t i = 1; i < t.size(); ++i)
                if (!number(t[i])) return refuse(objName, line.number);
            ++texCoords;
        } else if (keyword == "f") {
            if (t.size() < 4) return refuse(objName, line.number);
            std::vector<uint32_t> face;
            int64_t maxVt = 0;
            for (size_t i = 1; i < t.size(); ++i) {
                std::vector<std::string> parts(1);
                for (char ch : t[i]) {
                    if (ch == '/')
                        parts.emplace_back();
                    else
                        parts.back().push_back(ch);
                }
                // v, v/vt, v//vn, v/vt/vn: the texture index may be empty only before a normal.
                if (parts.size() > 3 || (parts.size() >= 2 && parts.back().empty()))
                    return refuse(objName, line.number);
                for (size_t k = 1; k < parts.size(); ++k) {
                    if (parts[k].empty()) continue;
                    const std::optional<int64_t> other = integer(parts[k]);
                    if (!other || *other == 0) return refuse(objName, line.number);
                    if (k == 1 && (*other < -texCoords || *other > (int64_t{1} << 30)))
                        return refuse(objName, line.number);
                    if (k == 1) maxVt = std::max(maxVt, *other);
                }
                const std::optional<int64_t> v = integer(parts[0]);
                const auto defined = static_cast<int64_t>(r.vertices.size());
                if (!v || *v == 0 || *v < -defined || *v > (int64_t{1} << 30))
                    return refuse(objName, line.number);
                face.push_back(static_cast<uint32_t>(*v < 0 ? defined + *v : *v - 1));
            }
            r.faces.push_back(std::move(face));
            faceMaxVt.push_back(maxVt);
            faceMaterial.push_back(useMtl);
            faceLine.push_back(line.number);
        } else if (keyword == "usemtl") {
            useMtl = rest(line.text, keyword);
            if (useMtl.empty()) return refuse(objName, line.number);
        } else if (keyword == "mtllib") {
            const std::string name = rest(line.text, keyword);
            if (name.empty()) return refuse(objName, line.number);
            if (!libraryRead) {
                libraryRead = true;
                if (const auto at = readMtl(mtl, materials)) return refuse(name, *at);
            }
        } else if (std::find(std::begin(kSkipped), std::end(kSkipped), keyword) ==
                   std::end(kSkipped)) {
            return refuse(objName, line.number);
        }
    }
    for (size_t f = 0; f < r.faces.size(); ++f) {
        for (uint32_t v : r.faces[f])
            if (v >= r.vertices.size()) return refuse(objName, faceLine[f]);
        if (faceMaxVt[f] > texCoords) return refuse(objName, faceLine[f]);
    }
    if (r.faces.empty()) return refuse(objName, 0);
    for (const vis::Vec3& p : r.vertices)
        if (std::fabs(p.x) > 0x1p59 || std::fabs(p.y) > 0x1p59 || std::fabs(p.z) > 0x1p59)
            return refuse(objName, 0);
    for (size_t f = 0; f < r.faces.size(); ++f) {
        const auto m = materials.find(faceMaterial[f]);
        if (m != materials.end() && m->second.emits) r.lights.push_back(static_cast<uint32_t>(f));
    }
    return r;
}

}  // namespace penumbra::test
