// The one place the project reads text it did not write: a whole file, a number, an integer, a
// value quoted into an error message, blanks around a token, the words of a line, a keyword in
// any case, a file name's extension. Every reader (OBJ, PLY/OFF/STL, glTF, JSON scenes,
// visibility files) and command line (penumbra, penumbra_pair_stats) takes these, so that one
// input is accepted or refused for the same reason everywhere. One number is read elsewhere: an
// ASCII STL coordinate, read straight into a float (strtof) as OpenMesh stores it (openmesh_io).
//
// The rules, chosen once:
//   - A number is the whole text, nothing around it (callers trim where blanks may surround it):
//     an optional sign, then decimal digits with an optional fraction and exponent, as
//     std::from_chars reads them (locale-independent; no hexadecimal), rounded correctly: the
//     double nearest the decimal text, the same on every machine.
//   - The sign is one character: '-', or a single '+' (from_chars takes no '+'; "+1.5" is 1.5).
//     "+-1", "-+1" and "++1" are refused: a second sign is a malformed number, never -1 or +1.
//   - A finite number is refused when it is NaN or an infinity ("nan", "inf", "infinity" in any
//     case), or beyond the range of a double (overflow, "1e400", and underflow to zero, "1e-400").
//   - An integer is a whole number of at most 64 bits in a range the caller names, with the same
//     sign rule ("-0" is 0).
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// ---- files --------------------------------------------------------------------------------------

// A file that could not be read whole: what() is "FILE: cannot read file: REASON", the reason
// being the system's ("No such file or directory", "Is a directory", "Permission denied").
struct FileReadError : std::runtime_error {
    FileReadError(std::string file, std::string reason);
    std::string file;
    std::string reason;
};

// "cannot read file: REASON": the message of a FileReadError without the file, for errors that
// name the file themselves (SceneError puts it first).
std::string cannotReadFile(std::string_view reason);

// The whole content of a file, byte for byte (no newline translation): text or binary. Throws
// FileReadError.
std::string readWholeFile(const std::filesystem::path& path);

// The same, as bytes, for the readers that decode binary data (visibility files, glTF buffers).
std::vector<unsigned char> readWholeFileBytes(const std::filesystem::path& path);

// readWholeFile for the scene readers: a file that cannot be read is a SceneError of that file
// (line 0) with the message cannotReadFile(reason).
std::string readSceneFile(const std::filesystem::path& path);

// ---- numbers ------------------------------------------------------------------------------------

// Why a text is not the number asked for.
enum class NumberFault {
    kMalformed,   // not a number: empty, junk before or after it, a second sign
    kOutOfRange,  // a number, beyond a double's range or the integer range asked for
    kNotFinite,   // NaN or an infinity
};

// The text as a finite double (the rules above); nullopt otherwise, with the reason in *fault
// when fault is given.
std::optional<double> parseFinite(std::string_view text, NumberFault* fault = nullptr);

// The inclusive range an integer must lie in.
struct IntegerRange {
    int64_t min = std::numeric_limits<int64_t>::min();
    int64_t max = std::numeric_limits<int64_t>::max();
};

// The text as an integer in `range` (the rules above); nullopt otherwise, with the reason in
// *fault when fault is given.
std::optional<int64_t> parseInteger(std::string_view text, IntegerRange range = {},
                                    NumberFault* fault = nullptr);

// ---- text ---------------------------------------------------------------------------------------

// Without the blanks around it (space, tab, CR, LF, VT, FF).
std::string_view trim(std::string_view text);

// The words of text (what lies between blanks, the same blanks), appended to `words`: a caller
// reading many lines keeps one vector and clears it.
void appendWords(std::string_view text, std::vector<std::string_view>& words);

// How an error message quotes a value: between single quotes, its first kQuotedLimit bytes and
// "..." when there were more; bytes outside printable ASCII as \xNN, so that a binary or hostile
// value can neither flood nor garble the message.
inline constexpr size_t kQuotedLimit = 60;
std::string quoteForMessage(std::string_view value);

// Whether a and b are the same text but for the case of ASCII letters ("Solid" and "solid").
bool equalsIgnoreCase(std::string_view a, std::string_view b);

// The file name's extension in lower case (ASCII), with its dot: ".obj" for "Model.OBJ", "" for
// none (std::filesystem's rule: ".hidden" has none).
std::string lowerExtension(const std::filesystem::path& path);

}  // namespace penumbra
