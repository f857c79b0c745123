#include "engine/io/openmesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "engine/io/text_input.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
namespace OMIO = OpenMesh::IO;

// Records what an OpenMesh reader produces, in call order, with no connectivity of its own.
class PolygonImporter final : public OMIO::BaseImporter {
  public:
    explicit PolygonImporter(vis::PolygonMesh& mesh) : mesh_(mesh) {}

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
        return add_vertex(OpenMesh::Vec3d(p[0], p[1], p[2]));
    }
    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
        mesh_.vertices.push_back({p[0], p[1], p[2]});
        return OpenMesh::VertexHandle(static_cast<int>(mesh_.vertices.size() - 1));
    }
    OpenMesh::VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
    OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
        return OpenMesh::HalfedgeHandle();
    }
    OpenMesh::FaceHandle add_face(const VHandles& indices) override {
        std::vector<uint32_t> face;
        face.reserve(indices.size());
        // A negative index becomes a huge one that validation reports as out of range.
        for (const OpenMesh::VertexHandle& v : indices)
            face.push_back(static_cast<uint32_t>(v.idx()));
        mesh_.faces.push_back(std::move(face));
        return OpenMesh::FaceHandle(static_cast<int>(mesh_.faces.size() - 1));
    }
    OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override {
        return OpenMesh::FaceHandle();
    }
    void set_point(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& p) override {
        if (v.idx() >= 0 && static_cast<size_t>(v.idx()) < mesh_.vertices.size())
            mesh_.vertices[static_cast<size_t>(v.idx())] = {p[0], p[1], p[2]};
    }

    // Everything else a reader may hand over is ignored.
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                            const std::vector<OpenMesh::Vec3f>&) override {}
    void set_face_texindex(OpenMesh::FaceHandle, int) override {}
    void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
    void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
    void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
    void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
    void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
    void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
    void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
    void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
    void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
    void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}

    size_t n_vertices() const override { return mesh_.vertices.size(); }
    size_t n_faces() const override { return mesh_.faces.size(); }
    size_t n_edges() const override { return 0; }
    void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
        // Header counts are untrusted: cap what is reserved up front.
        mesh_.vertices.reserve(std::min(nv, 1u << 24));
        mesh_.faces.reserve(std::min(nf, 1u << 24));
    }

  private:
    vis::PolygonMesh& mesh_;
};

// ---- PLY header ---------------------------------------------------------------------------------

struct PlyProperty {
    std::string name;
    bool list = false;
    int countSize = 0;  // bytes of a list's count (binary)
    int size = 0;       // bytes of the scalar, or of one list item
    bool countSigned = false;
    bool isFloat = false;  // a float or double scalar
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    enum Format { kAscii, kBinaryLittle, kBinaryBig } format = kAscii;
    std::vector<PlyElement> elements;
    size_t bodyOffset = 0;  // first byte after "end_header\n"
    int bodyLine = 0;       // 1-based line number of the first body line
    // Repair mode: header lines of no PLY keyword, skipped (byte ranges, their newline included),
    // and the warning that says so.
    std::vector<std::pair<size_t, size_t>> skippedLines;
    std::string skippedWarning;
    uint64_t count(std::string_view element) const {
        for (const PlyElement& e : elements)
            if (e.name == element) return e.count;
        return 0;
    }
};

int plyTypeSize(const std::string& t, bool* isSigned = nullptr) {
    static constexpr struct {
        const char* name;
        int size;
        bool isSigned;
    } kTypes[] = {
        {"char", 1, true},  {"int8", 1, true},    {"uchar", 1, false},  {"uint8", 1, false},
        {"short", 2, true}, {"int16", 2, true},   {"ushort", 2, false}, {"uint16", 2, false},
        {"int", 4, true},   {"int32", 4, true},   {"uint", 4, false},   {"uint32", 4, false},
        {"float", 4, true}, {"float32", 4, true}, {"double", 8, true},  {"float64", 8, true}};
    for (const auto& type : kTypes) {
        if (t == type.name) {
            if (isSigned) *isSigned = type.isSigned;
            return type.size;
        }
    }
    return 0;
}

// Where in the PLY header a check failed: the file and the line; the message starts "PLY header: ".
struct PlyHeaderLine {
    const std::string& file;
    int line;
    SceneError fail(const std::string& why) const {
        return makeSceneError(file, line, "PLY header: " + why);
    }
};

// A header line's whitespace-separated tokens.
std::vector<std::string> headerTokens(const std::string& line) {
    std::vector<std::string_view> words;
    appendWords(line, words);
    return {words.begin(), words.end()};
}

// "format ascii|binary_little_endian|binary_big_endian 1.0", once.
void readFormatLine(const std::vector<std::string>& tokens, const PlyHeaderLine& at,
                    PlyHeader& header, bool& sawFormat) {
    if (tokens.size() != 3) throw at.fail("malformed format line");
    if (tokens[1] == "ascii")
        header.format = PlyHeader::kAscii;
    else if (tokens[1] == "binary_little_endian")
        header.format = PlyHeader::kBinaryLittle;
    else if (tokens[1] == "binary_big_endian")
        header.format = PlyHeader::kBinaryBig;
    else
        throw at.fail("unknown format " + quoteForMessage(tokens[1]));
    // The only version there is; OpenMesh's reader loops forever on a version it cannot
    // parse as a number ("format ascii x"), so nothing else reaches it.
    if (tokens[2] != "1.0")
        throw at.fail("unsupported format version " + quoteForMessage(tokens[2]) +
                      " (only 1.0 exists)");
    if (sawFormat) throw at.fail("a second format line");
    sawFormat = true;
}

// "element NAME COUNT": the count in decimal digits only (at most 18 of them).
PlyElement readElementLine(const std::vector<std::string>& tokens, const PlyHeaderLine& at) {
    if (tokens.size() != 3) throw at.fail("malformed element line");
    PlyElement e;
    e.name = tokens[1];
    const std::string& n = tokens[2];
    if (n.empty() || n.size() > 18 ||
        !std::all_of(n.begin(), n.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw at.fail("element " + quoteForMessage(e.name) + ": bad count " + quoteForMessage(n));
    e.count = static_cast<uint64_t>(*parseInteger(n));
    return e;
}

// "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME", of the last element.
void readPropertyLine(const std::vector<std::string>& tokens, const PlyHeaderLine& at,
                      PlyHeader& header) {
    if (header.elements.empty()) throw at.fail("property before any element");
    PlyProperty p;
    if (tokens.size() == 5 && tokens[1] == "list") {
        p.list = true;
        p.name = tokens[4];
        p.countSize = plyTypeSize(tokens[2], &p.countSigned);
        p.size = plyTypeSize(tokens[3]);
        if (p.countSize == 0 || p.size == 0 || tokens[2] == "float" || tokens[2] == "float32" ||
            tokens[2] == "double" || tokens[2] == "float64")
            throw at.fail("property list with bad types " + quoteForMessage(tokens[2]) + " " +
                          quoteForMessage(tokens[3]));
    } else if (tokens.size() == 3) {
        p.name = tokens[2];
        p.size = plyTypeSize(tokens[1]);
        if (p.size == 0) throw at.fail("unknown property type " + quoteForMessage(tokens[1]));
        p.isFloat = tokens[1].rfind("float", 0) == 0 || tokens[1] == "double";
    } else {
        throw at.fail("malformed property line");
    }
    for (const PlyProperty& q : header.elements.back().properties)
        if (q.name == p.name)
            throw at.fail("element " + quoteForMessage(header.elements.back().name) +
                          ": property " + quoteForMessage(p.name) + " declared twice");
    header.elements.back().properties.push_back(p);
}

// Declarations a reader can rely on, before any reader sees the file: every item of an element
// takes at least one byte (a line, or a property's bytes), so no count may exceed the `body`
// bytes after the header (and an element without properties may have no items: a reader would
// spin through them reading nothing); vertices have x, y, z; faces a list of indices.
void checkPlyDeclarations(const PlyHeader& header, uint64_t body, const PlyHeaderLine& at) {
    for (size_t i = 0; i < header.elements.size(); ++i) {
        const PlyElement& e = header.elements[i];
        const std::string what = "element " + quoteForMessage(e.name);
        for (size_t j = 0; j < i; ++j)
            if (header.elements[j].name == e.name) throw at.fail(what + " declared twice");
        if (e.properties.empty() && e.count > 0)
            throw at.fail(what + " has " + std::to_string(e.count) + " items but no properties");
        if (e.count > body)
            throw at.fail(what + ": " + std::to_string(e.count) + " items cannot fit in the " +
                          std::to_string(body) + " bytes after the header");
        auto has = [&](const char* name, bool list) {
            for (const PlyProperty& p : e.properties)
                if (p.name == name && p.list == list) return true;
            return false;
        };
        if (e.name == "vertex" && !(has("x", false) && has("y", false) && has("z", false)))
            throw at.fail("element 'vertex' without scalar properties x, y and z");
        if (e.name == "face" && !has("vertex_indices", true) && !has("vertex_index", true))
            throw at.fail("element 'face' without a list property vertex_indices");
    }
}

// Parses and checks the header. A line of no PLY keyword (a tool's "Created by ..." outside a
// comment) is an error when `strict`, else skipped (PlyHeader::skippedLines).
PlyHeader parsePlyHeader(const std::string& data, const std::string& file, bool strict) {
    PlyHeader header;
    size_t pos = 0;
    int lineNo = 0;
    bool sawFormat = false;
    int firstSkipped = 0;
    std::string firstSkippedText;
    while (true) {
        const PlyHeaderLine at{file, lineNo};
        if (pos >= data.size() || lineNo > 100000)
            throw at.fail("no end_header (truncated header)");
        size_t end = data.find('\n', pos);
        if (end == std::string::npos) throw at.fail("no end_header (truncated header)");
        std::string line = data.substr(pos, end - pos);
        const size_t lineStart = pos;
        pos = end + 1;
        ++lineNo;
        const PlyHeaderLine here{file, lineNo};
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::vector<std::string> tokens = headerTokens(line);
        if (lineNo == 1) {
            if (tokens.size() != 1 || tokens[0] != "ply")
                throw here.fail("the file does not start with 'ply'");
            continue;
        }
        if (tokens.empty()) continue;
        const std::string& key = tokens[0];
        if (key == "comment" || key == "obj_info") continue;
        if (key == "end_header") break;
        if (key == "format") {
            readFormatLine(tokens, here, header, sawFormat);
        } else if (key == "element") {
            header.elements.push_back(readElementLine(tokens, here));
        } else if (key == "property") {
            readPropertyLine(tokens, here, header);
        } else {
            if (strict) throw here.fail("unknown keyword " + quoteForMessage(key));
            if (header.skippedLines.empty()) {
                firstSkipped = lineNo;
                firstSkippedText = line;
            }
            header.skippedLines.emplace_back(lineStart, pos);
        }
    }
    if (!header.skippedLines.empty()) {
        const size_t n = header.skippedLines.size();
        header.skippedWarning =
            file + ":" + std::to_string(firstSkipped) + ": PLY header: line " +
            quoteForMessage(trim(firstSkippedText)) +
            " is no header keyword (not a comment): skipped" +
            (n > 1 ? " with " + std::to_string(n - 1) + " more such lines" : std::string());
    }
    if (!sawFormat) throw makeSceneError(file, 0, "PLY header: no format line");
    checkPlyDeclarations(header, data.size() - pos, PlyHeaderLine{file, lineNo});
    header.bodyOffset = pos;
    header.bodyLine = lineNo + 1;
    return header;
}

uint64_t readUnsigned(const std::string& data, size_t at, int size, bool isSigned, bool bigEndian,
                      bool& negative) {
    uint64_t v = 0;
    for (int i = 0; i < size; ++i) {
        const auto byte = static_cast<unsigned char>(
            data[at + static_cast<size_t>(bigEndian ? i : size - 1 - i)]);
        v = (v << 8) | byte;
    }
    negative = isSigned && (v >> (8 * size - 1)) != 0;
    return v;
}

// Walks a binary PLY body: throws when an element ends past the end of the file. Returns the
// number of bytes after the last element.
size_t checkBinaryPlyBody(const std::string& data, const PlyHeader& header,
                          const std::string& file) {
    size_t pos = header.bodyOffset;
    const bool big = header.format == PlyHeader::kBinaryBig;
    for (const PlyElement& e : header.elements) {
        for (uint64_t item = 0; item < e.count; ++item) {
            for (const PlyProperty& p : e.properties) {
                const auto truncated = [&] {
                    return makeSceneError(
                        file, 0,
                        "truncated binary PLY: " + e.name + " " + std::to_string(item) + " of " +
                            std::to_string(e.count) + " ends past the end of the file (" +
                            std::to_string(data.size()) + " bytes)");
                };
                if (!p.list) {
                    if (data.size() - pos < static_cast<size_t>(p.size)) throw truncated();
                    pos += static_cast<size_t>(p.size);
                    continue;
                }
                if (data.size() - pos < static_cast<size_t>(p.countSize)) throw truncated();
                bool negative = false;
                const uint64_t n =
                    readUnsigned(data, pos, p.countSize, p.countSigned, big, negative);
                if (negative) {
                    throw makeSceneError(file, 0,
                                         "binary PLY: " + e.name + " " + std::to_string(item) +
                                             ": negative list length");
                }
                pos += static_cast<size_t>(p.countSize);
                if (n > (data.size() - pos) / static_cast<size_t>(p.size)) throw truncated();
                pos += n * static_cast<size_t>(p.size);
            }
        }
    }
    return data.size() - pos;
}

// ---- ASCII bodies -------------------------------------------------------------------------------

// Non-blank lines of a text from an offset, split into whitespace-separated tokens; `#` starts a
// comment when `comments` is set.
class TextLines {
  public:
    TextLines(const std::string& data, size_t offset, int firstLine, bool comments)
        : data_(data), pos_(offset), nextLine_(firstLine), comments_(comments) {}

    // The next line with at least one token; false at the end of the text.
    bool next(std::vector<std::string_view>& tokens) {
        tokens.clear();
        while (tokens.empty() && pos_ < data_.size()) {
            size_t end = data_.find('\n', pos_);
            if (end == std::string::npos) end = data_.size();
            std::string_view text = std::string_view(data_).substr(pos_, end - pos_);
            line_ = nextLine_++;
            pos_ = end + 1;
            if (comments_) text = text.substr(0, text.find('#'));
            appendWords(text, tokens);
        }
        return !tokens.empty();
    }
    int line() const { return line_; }

  private:
    const std::string& data_;
    size_t pos_;
    int nextLine_;
    int line_ = 0;
    bool comments_;
};

// A number beyond the coordinate contract (engine/scene/scene_validation.h), refused before
// OpenMesh reads it: its ASCII readers take numbers into floats and loop forever on one they cannot
// hold (a vertex at 1e155 hung the PLY reader).
std::optional<std::string> beyondContract(double v, std::string_view token) {
    if (std::fabs(v) <= kMaxCoordinate) return std::nullopt;
    return "number " + std::string(token) +
           " beyond the supported magnitude 2^59 = 5.8e17 (README, scene contract)";
}

// Checks an ASCII PLY body against its header: one line per element item with exactly the
// properties' tokens, numbers where numbers belong. OpenMesh misreads anything else silently.
void checkAsciiPlyBody(const std::string& data, const PlyHeader& header, const std::string& file) {
    TextLines lines(data, header.bodyOffset, header.bodyLine, false);
    std::vector<std::string_view> tokens;
    for (const PlyElement& e : header.elements) {
        for (uint64_t item = 0; item < e.count; ++item) {
            const std::string where = e.name + " " + std::to_string(item);
            if (!lines.next(tokens)) {
                throw makeSceneError(file, 0,
                                     "truncated ASCII PLY: the file ends before " + where +
                                         " (the header declares " + std::to_string(e.count) + ")");
            }
            size_t t = 0;
            const auto bad = [&](const std::string& why) {
                return makeSceneError(file, lines.line(), "ASCII PLY: " + where + ": " + why);
            };
            for (const PlyProperty& p : e.properties) {
                if (t >= tokens.size()) throw bad("too few values");
                if (!p.list) {
                    const std::optional<double> v =
                        p.isFloat
                            ? parseFinite(tokens[t])
                            : (parseInteger(tokens[t]) ? std::optional<double>(0.0) : std::nullopt);
                    if (!v) throw bad("bad or non-finite number " + quoteForMessage(tokens[t]));
                    if (const auto problem = beyondContract(*v, tokens[t])) throw bad(*problem);
                    ++t;
                    continue;
                }
                const std::optional<int64_t> n = parseInteger(tokens[t]);
                if (!n || *n < 0) throw bad("bad list length " + quoteForMessage(tokens[t]));
                ++t;
                if (static_cast<uint64_t>(*n) > tokens.size() - t) throw bad("too few values");
                for (int64_t k = 0; k < *n; ++k, ++t) {
                    if (!parseInteger(tokens[t]))
                        throw bad("bad integer " + quoteForMessage(tokens[t]));
                }
            }
            if (t != tokens.size()) throw bad("too many values");
        }
    }
}

// An ASCII OFF file checked token by token and rewritten in the plainest form for OpenMesh to read:
// keyword "OFF", the counts, each vertex as its three coordinates (printed back exactly, %.17g),
// each face as its count and indices. Comments, blank lines, '+' signs, colours, normals and
// texture coordinates go (the importer ignores them anyway): OpenMesh's reader misreads or loops
// on several of these (fuzz findings kept in tests/fuzz/regressions/off/).
struct CleanOff {
    uint64_t vertices = 0, faces = 0;
    std::string text;
};

// One OFF vertex line: at least three finite numbers within the coordinate contract (what follows
// x y z, a colour or a normal, is checked and left out); x y z written to `text` exactly.
void cleanOffVertex(const std::vector<std::string_view>& tokens, uint64_t v, int line,
                    const std::string& file, std::string& text) {
    if (tokens.size() < 3)
        throw makeSceneError(file, line, "OFF: vertex " + std::to_string(v) + ": too few values");
    for (size_t k = 0; k < tokens.size(); ++k) {
        const std::optional<double> x = parseFinite(tokens[k]);
        if (!x) {
            throw makeSceneError(file, line,
                                 "OFF: vertex " + std::to_string(v) +
                                     ": bad or non-finite number " + quoteForMessage(tokens[k]));
        }
        if (const auto problem = beyondContract(*x, tokens[k]))
            throw makeSceneError(file, line, "OFF: vertex " + std::to_string(v) + ": " + *problem);
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", *parseFinite(tokens[0]),
                  *parseFinite(tokens[1]), *parseFinite(tokens[2]));
    text += buf;
}

// One OFF face line: a vertex count of 3 or more, that many indices of existing vertices, and at
// most a colour after them (checked and left out); the count and indices written to `text`.
void cleanOffFace(const std::vector<std::string_view>& tokens, uint64_t f, uint64_t vertices,
                  int line, const std::string& file, std::string& text) {
    const std::string where = "OFF: face " + std::to_string(f) + ": ";
    const std::optional<int64_t> n = parseInteger(tokens[0]);
    if (!n || *n < 0 || static_cast<uint64_t>(*n) > tokens.size() - 1)
        throw makeSceneError(file, line, where + "bad vertex count or too few indices");
    // OpenMesh's reader spins, allocating without end, on a face of no vertices followed by
    // junk (found by scripts/fuzz.sh): a face has 3 or more vertices, and what may follow its
    // indices is a colour of at most 4 numbers.
    if (*n < 3)
        throw makeSceneError(file, line,
                             where + "a face needs at least 3 vertices, not " + std::to_string(*n));
    const size_t extra = tokens.size() - 1 - static_cast<size_t>(*n);
    if (extra > 4)
        throw makeSceneError(
            file, line,
            where + std::to_string(extra) + " values after the indices (a colour has at most 4)");
    for (size_t k = static_cast<size_t>(*n) + 1; k < tokens.size(); ++k)
        if (!parseFinite(tokens[k]))
            throw makeSceneError(
                file, line,
                where + "colour value " + quoteForMessage(tokens[k]) + " is not a number");
    for (int64_t k = 1; k <= *n; ++k) {
        const std::optional<int64_t> i = parseInteger(tokens[static_cast<size_t>(k)]);
        if (!i || *i < 0 || static_cast<uint64_t>(*i) >= vertices) {
            throw makeSceneError(
                file, line,
                where + "vertex index " + quoteForMessage(tokens[static_cast<size_t>(k)]) +
                    " out of range (the file has " + std::to_string(vertices) + " vertices)");
        }
    }
    text += std::to_string(*n);
    for (int64_t k = 1; k <= *n; ++k)
        text += " " + std::to_string(*parseInteger(tokens[static_cast<size_t>(k)]));
    text += '\n';
}

CleanOff cleanAsciiOff(const std::string& data, const std::string& file) {
    TextLines lines(data, 0, 1, true);
    std::vector<std::string_view> tokens;
    if (!lines.next(tokens)) throw makeSceneError(file, 0, "OFF: empty file");
    const std::string keyword(tokens[0]);
    const bool isOff = keyword.size() >= 3 && keyword.compare(keyword.size() - 3, 3, "OFF") == 0 &&
                       keyword.find_first_not_of("STCN") == keyword.size() - 3;
    if (!isOff)
        throw makeSceneError(file, lines.line(),
                             "OFF: the file does not start with an OFF keyword");
    if (tokens.size() > 1 && tokens[1] == "BINARY")
        throw makeSceneError(file, lines.line(), "OFF: binary OFF is not supported");
    CleanOff out;
    out.text = "OFF\n";
    // The counts may follow the keyword on its line.
    std::vector<std::string_view> counts(tokens.begin() + 1, tokens.end());
    if (counts.empty()) {
        if (!lines.next(tokens)) throw makeSceneError(file, 0, "OFF: no counts line");
        counts = tokens;
    }
    if (counts.size() < 2 || counts.size() > 3)
        throw makeSceneError(file, lines.line(), "OFF: expected the counts 'vertices faces edges'");
    const std::optional<int64_t> nv = parseInteger(counts[0]), nf = parseInteger(counts[1]);
    if (!nv || !nf || *nv < 0 || *nf < 0 || static_cast<uint64_t>(*nv) > kMaxSceneElements ||
        static_cast<uint64_t>(*nf) > kMaxSceneElements)
        throw makeSceneError(file, lines.line(), "OFF: bad vertex or face count");
    out.vertices = static_cast<uint64_t>(*nv);
    out.faces = static_cast<uint64_t>(*nf);
    out.text += std::to_string(out.vertices) + " " + std::to_string(out.faces) + " 0\n";
    for (uint64_t v = 0; v < out.vertices; ++v) {
        if (!lines.next(tokens)) {
            throw makeSceneError(file, 0,
                                 "truncated OFF: the file ends before vertex " + std::to_string(v) +
                                     " (the header declares " + std::to_string(out.vertices) +
                                     " vertices)");
        }
        cleanOffVertex(tokens, v, lines.line(), file, out.text);
    }
    for (uint64_t f = 0; f < out.faces; ++f) {
        if (!lines.next(tokens)) {
            throw makeSceneError(file, 0,
                                 "truncated OFF: the file ends before face " + std::to_string(f) +
                                     " (the header declares " + std::to_string(out.faces) +
                                     " faces)");
        }
        cleanOffFace(tokens, f, out.vertices, lines.line(), file, out.text);
    }
    return out;
}

// ---- STL ----------------------------------------------------------------------------------------

struct StlFacts {
    bool binary = false;
    uint64_t facets = 0;
    std::vector<uint64_t> coincident;  // facets whose corners coincide (skipped by OpenMesh)
    std::vector<std::array<float, 9>> coincidentCorners;  // their corners
    // ASCII: every solid's facets as one solid in the plainest form, for OpenMesh to read, and
    // the line of each facet (its "facet" keyword).
    std::string text;
    std::vector<int32_t> facetLines;
};

bool sameCorner(const float* a, const float* b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// A binary STL's facts, when the file's size is the one its header's facet count gives (84 bytes
// and 50 a facet): its corners must be finite. False when it is no binary STL.
bool inspectBinaryStl(const std::string& data, const std::string& file, StlFacts& facts) {
    if (data.size() < 84) return false;
    uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) n = __builtin_bswap32(n);
    if (84 + 50 * uint64_t{n} != data.size()) return false;
    facts.binary = true;
    facts.facets = n;
    for (uint64_t f = 0; f < n; ++f) {
        float c[12];
        std::memcpy(c, data.data() + 84 + 50 * f, sizeof c);
        for (float x : c) {
            if (!std::isfinite(x)) {
                throw makeSceneError(
                    file, 0, "facet " + std::to_string(f) + ": non-finite number in binary STL");
            }
        }
        if (sameCorner(c + 3, c + 6) || sameCorner(c + 3, c + 9) || sameCorner(c + 6, c + 9)) {
            facts.coincident.push_back(f);
            std::array<float, 9>& corners = facts.coincidentCorners.emplace_back();
            std::copy(c + 3, c + 12, corners.begin());
        }
    }
    return true;
}

// Why a file that starts with no "solid" is no STL: as a binary one, too short or of another size.
SceneError notAnStl(const std::string& data, const std::string& file) {
    std::string why = "malformed or truncated binary STL: ";
    if (data.size() < 84) {
        why += "only " + std::to_string(data.size()) + " bytes (the header alone has 84)";
    } else {
        uint32_t n = 0;
        std::memcpy(&n, data.data() + 80, 4);
        why += "the header declares " + std::to_string(n) + " triangles, which take " +
               std::to_string(84 + 50 * uint64_t{n}) + " bytes, but the file has " +
               std::to_string(data.size());
    }
    return makeSceneError(file, 0, why);
}

// An ASCII STL's text from an offset, token by token, counting lines.
class StlTokens {
  public:
    StlTokens(const std::string& data, size_t start) : data_(data), pos_(start) {
        for (size_t i = 0; i < start; ++i) line_ += data[i] == '\n';
    }
    // The next whitespace-separated token; false at the end of the text.
    bool next(std::string_view& token) {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) {
            line_ += data_[pos_] == '\n';
            ++pos_;
        }
        const size_t b = pos_;
        while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_])))
            ++pos_;
        token = std::string_view(data_).substr(b, pos_ - b);
        return !token.empty();
    }
    void skipRestOfLine() {
        while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
    }
    int line() const { return line_; }

  private:
    const std::string& data_;
    size_t pos_;
    int line_ = 1;
};

// An ASCII facet's end: its three corners checked, noted when two coincide, and written out again.
void endAsciiFacet(StlFacts& facts, std::vector<float>& corners, int32_t& facetLine, int line,
                   const std::string& file) {
    if (corners.size() != 9) {
        throw makeSceneError(file, line,
                             "ASCII STL: facet " + std::to_string(facts.facets) + " has " +
                                 std::to_string(corners.size() / 3) + " vertices (expected 3)");
    }
    const float* c = corners.data();
    if (sameCorner(c, c + 3) || sameCorner(c, c + 6) || sameCorner(c + 3, c + 6)) {
        facts.coincident.push_back(facts.facets);
        std::array<float, 9>& kept = facts.coincidentCorners.emplace_back();
        std::copy(c, c + 9, kept.begin());
    }
    facts.text += "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
        char buf[64];
        // Nine significant digits give the float back exactly.
        std::snprintf(buf, sizeof buf, "vertex %.9g %.9g %.9g\n", double(c[3 * k]),
                      double(c[3 * k + 1]), double(c[3 * k + 2]));
        facts.text += buf;
    }
    facts.text += "endloop\nendfacet\n";
    facts.facetLines.push_back(facetLine);
    facetLine = 0;
    corners.clear();
    ++facts.facets;
}

// ASCII: count facets, check corners are finite, find facets with coinciding corners, and write
// the facets out again as one solid. A file may hold several solids one after the other ("solid
// a ... endsolid a solid b ... endsolid b", as tools concatenate them): all are read. Anything
// after the last endsolid that does not start another solid is ignored.
void inspectAsciiStl(const std::string& data, size_t start, const std::string& file,
                     StlFacts& facts) {
    std::vector<float> corners;
    StlTokens tokens(data, start);
    facts.text = "solid penumbra\n";
    std::string_view token;
    tokens.next(token);       // "solid"
    tokens.skipRestOfLine();  // the solid's name
    bool endSolid = false;
    int32_t facetLine = 0;
    while (tokens.next(token)) {
        const auto is = [&token](std::string_view keyword) {
            return equalsIgnoreCase(token, keyword);
        };
        if (endSolid) {
            // Between solids: another one, or the end of what is read.
            if (!is("solid")) break;
            endSolid = false;
            tokens.skipRestOfLine();
            continue;
        }
        if (is("facet")) {
            facetLine = tokens.line();
        } else if (is("vertex")) {
            if (facetLine == 0) facetLine = tokens.line();
            for (int k = 0; k < 3; ++k) {
                std::string_view num;
                if (!tokens.next(num))
                    throw makeSceneError(file, tokens.line(), "ASCII STL: truncated vertex");
                const std::string s(num);
                char* endPtr = nullptr;
                const float v = std::strtof(s.c_str(), &endPtr);
                if (endPtr != s.c_str() + s.size() || !std::isfinite(v)) {
                    throw makeSceneError(file, tokens.line(),
                                         "ASCII STL: facet " + std::to_string(facts.facets) +
                                             ": bad vertex coordinate " + quoteForMessage(s));
                }
                corners.push_back(v);
            }
        } else if (is("endfacet")) {
            endAsciiFacet(facts, corners, facetLine, tokens.line(), file);
        } else if (is("endsolid")) {
            if (!corners.empty()) {
                throw makeSceneError(file, tokens.line(),
                                     "ASCII STL: facet " + std::to_string(facts.facets) +
                                         " has no endfacet before endsolid");
            }
            endSolid = true;
            tokens.skipRestOfLine();  // the solid's name
        }
    }
    if (!endSolid) throw makeSceneError(file, 0, "ASCII STL: no endsolid (truncated file)");
    facts.text += "endsolid penumbra\n";
}

StlFacts inspectStl(const std::string& data, const std::string& file) {
    StlFacts facts;
    if (inspectBinaryStl(data, file, facts)) return facts;
    size_t start = 0;
    while (start < data.size() && std::isspace(static_cast<unsigned char>(data[start]))) ++start;
    if (!equalsIgnoreCase(std::string_view(data).substr(start, 5), "solid"))
        throw notAnStl(data, file);
    inspectAsciiStl(data, start, file, facts);
    return facts;
}

// OpenMesh skips the STL facets whose corners coincide: they are put back in their place, as
// triangles of the vertices at their corners (existing ones where OpenMesh merged that corner,
// else new), so that face numbers are facet numbers and checkLoadedFaces drops them (or refuses
// them) with every other degenerate face, in one warning.
void restoreCoincidentFacets(vis::PolygonMesh& mesh, const StlFacts& stl) {
    struct Key {
        double x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Hash {
        size_t operator()(const Key& k) const {
            const std::hash<double> h;
            return h(k.x) ^ (h(k.y) * 31) ^ (h(k.z) * 1000003);
        }
    };
    std::unordered_map<Key, uint32_t, Hash> byPosition;
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        const Vec3& p = mesh.vertices[v];
        byPosition.emplace(Key{p.x, p.y, p.z}, static_cast<uint32_t>(v));
    }
    std::vector<std::vector<uint32_t>> faces;
    faces.reserve(stl.facets);
    size_t read = 0, skipped = 0;
    for (uint64_t facet = 0; facet < stl.facets; ++facet) {
        if (skipped < stl.coincident.size() && stl.coincident[skipped] == facet) {
            const std::array<float, 9>& c = stl.coincidentCorners[skipped++];
            std::vector<uint32_t> face;
            for (int k = 0; k < 3; ++k) {
                const Key key{c[3 * k], c[3 * k + 1], c[3 * k + 2]};
                const auto [it, added] =
                    byPosition.emplace(key, static_cast<uint32_t>(mesh.vertices.size()));
                if (added) mesh.vertices.push_back({key.x, key.y, key.z});
                face.push_back(it->second);
            }
            faces.push_back(std::move(face));
        } else {
            faces.push_back(std::move(mesh.faces[read++]));
        }
    }
    mesh.faces = std::move(faces);
}

// A file checked before OpenMesh reads it: the counts OpenMesh must find, and the text it is to
// read instead of the file where the checks rewrote it.
struct CheckedFile {
    uint64_t vertices = 0, faces = 0;
    bool checkVertexCount = true;  // false for STL: OpenMesh merges its corners
    std::string text;              // empty: OpenMesh reads the file itself
    std::vector<std::string> warnings;
    StlFacts stl;
};

CheckedFile checkPly(const std::string& data, const std::string& file, const LoadOptions& options) {
    CheckedFile checked;
    const PlyHeader header = parsePlyHeader(data, file, options.strict);
    checked.vertices = header.count("vertex");
    checked.faces = header.count("face");
    std::string trailingWarning;
    if (header.format == PlyHeader::kAscii) {
        checkAsciiPlyBody(data, header, file);
    } else {
        const size_t extra = checkBinaryPlyBody(data, header, file);
        if (extra > 0) {
            trailingWarning =
                file + ": " + std::to_string(extra) + " bytes after the last PLY element ignored";
        }
    }
    if (!header.skippedLines.empty()) {
        // The PLY without its skipped header lines.
        checked.warnings.push_back(header.skippedWarning);
        size_t from = 0;
        for (const auto& [begin, end] : header.skippedLines) {
            checked.text.append(data, from, begin - from);
            from = end;
        }
        checked.text.append(data, from, std::string::npos);
    }
    if (!trailingWarning.empty()) checked.warnings.push_back(trailingWarning);
    return checked;
}

CheckedFile checkOff(const std::string& data, const std::string& file) {
    CleanOff off = cleanAsciiOff(data, file);
    CheckedFile checked;
    checked.vertices = off.vertices;
    checked.faces = off.faces;
    checked.text = std::move(off.text);
    return checked;
}

CheckedFile checkStl(const std::string& data, const std::string& file, const LoadOptions& options) {
    CheckedFile checked;
    StlFacts& stl = checked.stl;
    stl = inspectStl(data, file);
    checked.faces = stl.facets - stl.coincident.size();
    checked.checkVertexCount = false;  // merged corners
    if (!stl.coincident.empty() && options.faces == DegenerateFaces::kReject) {
        const uint64_t first = stl.coincident.front();
        throw makeSceneError(file, first < stl.facetLines.size() ? stl.facetLines[first] : 0,
                             "face " + std::to_string(first) +
                                 ": degenerate (zero area): two corners coincide (" +
                                 std::to_string(stl.coincident.size()) + " such facets)");
    }
    if (!stl.binary) checked.text = std::move(stl.text);
    return checked;
}

// OpenMesh's reading of the checked file into scene.mesh, held to the counts the checks found
// and to finite coordinates.
void readWithOpenMesh(const CheckedFile& checked, const std::string& format,
                      const std::string& file, Scene& scene) {
    PolygonImporter importer(scene.mesh);
    OMIO::Options readOptions = OMIO::Options::Default;
    bool read = false;
    if (!checked.text.empty()) {
        std::istringstream in(checked.text);
        read = OMIO::IOManager().read(in, format, importer, readOptions);
    } else {
        read = OMIO::IOManager().read(file, importer, readOptions);
    }
    if (!read) {
        throw makeSceneError(file, 0, "OpenMesh could not read the file (malformed or truncated)");
    }
    if ((checked.checkVertexCount && scene.mesh.vertices.size() != checked.vertices) ||
        scene.mesh.faces.size() != checked.faces) {
        throw makeSceneError(
            file, 0,
            "malformed or truncated: expected " +
                (checked.checkVertexCount ? std::to_string(checked.vertices) + " vertices and "
                                          : "") +
                std::to_string(checked.faces) + " faces, OpenMesh read " +
                std::to_string(scene.mesh.vertices.size()) + " and " +
                std::to_string(scene.mesh.faces.size()));
    }
    for (size_t v = 0; v < scene.mesh.vertices.size(); ++v) {
        const Vec3& p = scene.mesh.vertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw makeSceneError(file, 0,
                                 "vertex " + std::to_string(v) + ": non-finite coordinate");
    }
}

}  // namespace

Scene loadOpenMeshFile(const fs::path& path, const LoadOptions& options) {
    const std::string file = path.string();
    const std::string extension = lowerExtension(path);
    if (extension != ".ply" && extension != ".off" && extension != ".stl") {
        throw makeSceneError(file, 0, "not a PLY, OFF or STL file name");
    }
    const std::string data = readSceneFile(path);
    if (data.empty()) throw makeSceneError(file, 0, "empty file");

    CheckedFile checked = extension == ".ply"   ? checkPly(data, file, options)
                          : extension == ".off" ? checkOff(data, file)
                                                : checkStl(data, file, options);
    if (checked.vertices >= kMaxSceneElements || checked.faces >= kMaxSceneElements) {
        throw makeSceneError(file, 0, "too many elements in the header");
    }
    Scene scene;
    scene.sourcePath = file;
    readWithOpenMesh(checked, extension.substr(1), file, scene);
    scene.warnings = std::move(checked.warnings);

    const StlFacts& stl = checked.stl;
    if (!stl.coincident.empty()) restoreCoincidentFacets(scene.mesh, stl);
    if (extension == ".stl" && !stl.binary)
        scene.faceSourceLine = std::move(checked.stl.facetLines);
    scene.faceMaterial.assign(scene.mesh.faces.size(), -1);
    checkLoadedFaces(scene, options.faces);
    return scene;
}

}  // namespace penumbra
