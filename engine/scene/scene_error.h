// SceneError: the one exception type for anything wrong with a scene file or a Scene.
//
// what() reads "path/to/file.obj:17: face 12: vertex index 40 out of range (file has 38 vertices)":
// the file, the 1-based line, then the message. Line 0 means "no particular line" and is left out
// ("path/to/file.obj: no faces"). `kind` tells a file that is not there from a scene that is wrong,
// for a caller that acts on the difference (the bench skips a scene whose meshes are not fetched)
// without reading the message.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace penumbra {

// "file:line: message", or "file: message" when line is 0 (or negative).
inline std::string formatSceneError(std::string_view file, int64_t line, std::string_view message) {
    std::string s(file);
    if (line > 0) {
        s += ':';
        s += std::to_string(line);
    }
    s += ": ";
    s += message;
    return s;
}

struct SceneError : std::runtime_error {
    enum class Kind {
        Invalid,      // the scene (or a file it names) is malformed or breaks the contract
        MissingFile,  // a file to read does not exist: the scene file, or a mesh a JSON scene names
    };

    SceneError(std::string file_, int64_t line_, std::string_view message_)
        : std::runtime_error(formatSceneError(file_, line_, message_)),
          file(std::move(file_)),
          line(line_),
          message(message_) {}

    std::string file;     // the file (or source name) the error is about
    int64_t line;         // 1-based line in `file`, 0 when not about one line
    std::string message;  // the message without the "file:line: " prefix
    Kind kind = Kind::Invalid;
    std::string missingFile;  // Kind::MissingFile: the path of the file that does not exist
};

// The helper the readers, the validator and the writer build their errors with.
inline SceneError makeSceneError(std::string_view file, int64_t line, std::string_view message) {
    return SceneError(std::string(file), line, message);
}

// The error for a file to read that does not exist (`missing`, as the scene names it, joined to
// the scene's directory), reported against `file`.
inline SceneError makeMissingFileError(std::string_view file, int64_t line,
                                       std::string_view message, std::string missing) {
    SceneError e(std::string(file), line, message);
    e.kind = SceneError::Kind::MissingFile;
    e.missingFile = std::move(missing);
    return e;
}

}  // namespace penumbra
