#include "engine/io/text_input.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <system_error>

#include "engine/scene/scene_error.h"

namespace penumbra {
namespace text_input_detail {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string systemReason(int err) {
    return std::error_code(err, std::generic_category()).message();
}

// The whole file, into a string or a vector of bytes.
template <typename Bytes>
Bytes readAll(const std::filesystem::path& path) {
    const std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw FileReadError(path.string(), systemReason(errno));
    Bytes out;
    std::error_code ec;
    if (const uintmax_t size = std::filesystem::file_size(path, ec); !ec)
        out.reserve(static_cast<size_t>(size));
    char buffer[1 << 16];
    size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0)
        out.insert(out.end(), buffer, buffer + n);
    // A directory opens, then fails to read (EISDIR): the system's reason names it.
    if (std::ferror(file.get())) throw FileReadError(path.string(), systemReason(errno));
    return out;
}

// The text as from_chars is to read it, under the sign rule: a leading '+' removed (from_chars
// takes none, and reads a '-' itself); nullopt when a second sign follows the first.
std::optional<std::string_view> withoutPlus(std::string_view text) {
    const auto sign = [](char c) { return c == '+' || c == '-'; };
    if (text.size() > 1 && sign(text[0]) && sign(text[1])) return std::nullopt;
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    return text;
}

// What trim and appendWords take for blanks: C's isspace in the "C" locale.
constexpr std::string_view kBlanks = " \t\r\n\v\f";

char asciiLower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

std::nullopt_t fail(NumberFault* fault, NumberFault why) {
    if (fault) *fault = why;
    return std::nullopt;
}

// The whole text as a T (the sign rule applied), or the fault: malformed, or beyond T's range.
template <typename T>
std::optional<T> whole(std::string_view text, NumberFault* fault) {
    const std::optional<std::string_view> s = withoutPlus(text);
    if (!s) return fail(fault, NumberFault::kMalformed);
    T value{};
    const auto [end, ec] = std::from_chars(s->data(), s->data() + s->size(), value);
    if (end != s->data() + s->size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
        return fail(fault, NumberFault::kMalformed);
    if (ec == std::errc::result_out_of_range) return fail(fault, NumberFault::kOutOfRange);
    return value;
}

}  // namespace text_input_detail

FileReadError::FileReadError(std::string file_, std::string reason_)
    : std::runtime_error(file_ + ": " + cannotReadFile(reason_)),
      file(std::move(file_)),
      reason(std::move(reason_)) {}

std::string cannotReadFile(std::string_view reason) {
    return "cannot read file: " + std::string(reason);
}

std::string readWholeFile(const std::filesystem::path& path) {
    return text_input_detail::readAll<std::string>(path);
}

std::vector<unsigned char> readWholeFileBytes(const std::filesystem::path& path) {
    return text_input_detail::readAll<std::vector<unsigned char>>(path);
}

std::string readSceneFile(const std::filesystem::path& path) {
    try {
        return readWholeFile(path);
    } catch (const FileReadError& e) {
        throw makeSceneError(e.file, 0, cannotReadFile(e.reason));
    }
}

std::optional<double> parseFinite(std::string_view text, NumberFault* fault) {
    const std::optional<double> value = text_input_detail::whole<double>(text, fault);
    if (value && !std::isfinite(*value))
        return text_input_detail::fail(fault, NumberFault::kNotFinite);
    return value;
}

std::optional<int64_t> parseInteger(std::string_view text, IntegerRange range, NumberFault* fault) {
    const std::optional<int64_t> value = text_input_detail::whole<int64_t>(text, fault);
    if (value && (*value < range.min || *value > range.max))
        return text_input_detail::fail(fault, NumberFault::kOutOfRange);
    return value;
}

std::string_view trim(std::string_view text) {
    const size_t first = text.find_first_not_of(text_input_detail::kBlanks);
    if (first == std::string_view::npos) return {};
    return text.substr(first, text.find_last_not_of(text_input_detail::kBlanks) - first + 1);
}

void appendWords(std::string_view text, std::vector<std::string_view>& words) {
    using text_input_detail::kBlanks;
    for (size_t begin = text.find_first_not_of(kBlanks); begin != std::string_view::npos;) {
        const size_t end = std::min(text.find_first_of(kBlanks, begin), text.size());
        words.push_back(text.substr(begin, end - begin));
        begin = text.find_first_not_of(kBlanks, end);
    }
}

std::string quoteForMessage(std::string_view value) {
    std::string out = "'";
    for (const char c : value.substr(0, kQuotedLimit)) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte < 0x7f) {
            out += c;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", byte);
            out += hex;
        }
    }
    if (value.size() > kQuotedLimit) out += "...";
    return out + "'";
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (text_input_detail::asciiLower(a[i]) != text_input_detail::asciiLower(b[i]))
            return false;
    return true;
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = text_input_detail::asciiLower(c);
    return extension;
}

}  // namespace penumbra
