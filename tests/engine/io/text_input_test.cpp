// Tests of the one text-input helper (engine/io/text_input.h): each expectation is worked out by
// hand from the rules in the header, not captured from the code.
#include "engine/io/text_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "engine/scene/scene_error.h"
#include "tests/support/loader_test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// The fault parseFinite reports for `text` (and that it returned no value).
NumberFault finiteFault(std::string_view text) {
    NumberFault fault{};
    EXPECT_FALSE(parseFinite(text, &fault).has_value()) << "'" << text << "' was accepted";
    return fault;
}

NumberFault integerFault(std::string_view text, IntegerRange range = {}) {
    NumberFault fault{};
    EXPECT_FALSE(parseInteger(text, range, &fault).has_value()) << "'" << text << "' was accepted";
    return fault;
}

// ---- finite numbers -----------------------------------------------------------------------------

TEST(ParseFinite, ReadsDecimalNumbersWhole) {
    EXPECT_EQ(parseFinite("0"), 0.0);
    EXPECT_EQ(parseFinite("1.5"), 1.5);
    EXPECT_EQ(parseFinite("-2.25"), -2.25);
    EXPECT_EQ(parseFinite(".5"), 0.5);
    EXPECT_EQ(parseFinite("1."), 1.0);
    EXPECT_EQ(parseFinite("3e2"), 300.0);
    EXPECT_EQ(parseFinite("-1.25E-2"), -0.0125);
    // The largest double and the smallest subnormal are in range.
    EXPECT_EQ(parseFinite("1.7976931348623157e308"), std::numeric_limits<double>::max());
    EXPECT_EQ(parseFinite("4.9406564584124654e-324"), std::numeric_limits<double>::denorm_min());
    // "-0" is negative zero, a finite number.
    const std::optional<double> minusZero = parseFinite("-0");
    ASSERT_TRUE(minusZero.has_value());
    EXPECT_TRUE(*minusZero == 0.0 && std::signbit(*minusZero));
}

TEST(ParseFinite, TakesOneLeadingPlusAndNoSecondSign) {
    EXPECT_EQ(parseFinite("+1.5"), 1.5);
    EXPECT_EQ(parseFinite("+0"), 0.0);
    EXPECT_EQ(parseFinite("+.5"), 0.5);
    // A second sign is a malformed number, never -1 or +1 (openmesh_io once read "+-1" as -1).
    EXPECT_EQ(finiteFault("+-1"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("-+1"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("++1"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("--1"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("+"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("-"), NumberFault::kMalformed);
    EXPECT_EQ(finiteFault("1+"), NumberFault::kMalformed);
}

TEST(ParseFinite, RefusesNaNAndInfinityAsNotFinite) {
    for (const char* text :
         {"nan", "NaN", "-nan", "+nan", "inf", "-inf", "+inf", "INF", "infinity", "-Infinity"})
        EXPECT_EQ(finiteFault(text), NumberFault::kNotFinite) << text;
}

TEST(ParseFinite, RefusesNumbersBeyondADoubleAsOutOfRange) {
    EXPECT_EQ(finiteFault("1e309"), NumberFault::kOutOfRange);
    EXPECT_EQ(finiteFault("-1e400"), NumberFault::kOutOfRange);
    EXPECT_EQ(finiteFault("+1e400"), NumberFault::kOutOfRange);
    // Underflow to zero as well: the text names a number a double cannot hold.
    EXPECT_EQ(finiteFault("1e-400"), NumberFault::kOutOfRange);
    // Out of range and followed by junk: not a number at all.
    EXPECT_EQ(finiteFault("1e400x"), NumberFault::kMalformed);
}

TEST(ParseFinite, RefusesEmptyTextBlanksAndTrailingJunkAsMalformed) {
    for (const char* text : {"", " ", "1 ", " 1", "1.5x", "1,5", "1e", "1e+", "0x10", "x1", "1..2",
                             "1e5.5", "\t2", "3\n"})
        EXPECT_EQ(finiteFault(text), NumberFault::kMalformed) << "'" << text << "'";
    // A NUL byte inside the text is junk too (the text is a view, not a C string).
    EXPECT_EQ(finiteFault(std::string_view("1\0", 2)), NumberFault::kMalformed);
}

TEST(ParseFinite, LeavesFaultAloneOnSuccessAndAcceptsNoFault) {
    NumberFault fault = NumberFault::kNotFinite;
    EXPECT_EQ(parseFinite("2", &fault), 2.0);
    EXPECT_EQ(fault, NumberFault::kNotFinite);
    EXPECT_FALSE(parseFinite("junk").has_value());  // no fault pointer: no crash
}

// ---- integers -----------------------------------------------------------------------------------

TEST(ParseInteger, ReadsWholeNumbersWithTheSameSignRule) {
    EXPECT_EQ(parseInteger("0"), 0);
    EXPECT_EQ(parseInteger("42"), 42);
    EXPECT_EQ(parseInteger("-7"), -7);
    EXPECT_EQ(parseInteger("+7"), 7);
    EXPECT_EQ(parseInteger("-0"), 0);
    EXPECT_EQ(parseInteger("007"), 7);
    EXPECT_EQ(parseInteger("9223372036854775807"), INT64_MAX);
    EXPECT_EQ(parseInteger("-9223372036854775808"), INT64_MIN);
    EXPECT_EQ(integerFault("+-1"), NumberFault::kMalformed);
    EXPECT_EQ(integerFault("-+1"), NumberFault::kMalformed);
    EXPECT_EQ(integerFault("++1"), NumberFault::kMalformed);
    EXPECT_EQ(integerFault("+"), NumberFault::kMalformed);
}

TEST(ParseInteger, RefusesFractionsJunkAndEmptyTextAsMalformed) {
    for (const char* text : {"", " 1", "1 ", "1.0", "1e3", "1.", "0x1f", "12a", "nan", "inf"})
        EXPECT_EQ(integerFault(text), NumberFault::kMalformed) << "'" << text << "'";
}

TEST(ParseInteger, RefusesValuesBeyond64BitsOrTheRangeAskedAsOutOfRange) {
    EXPECT_EQ(integerFault("9223372036854775808"), NumberFault::kOutOfRange);
    EXPECT_EQ(integerFault("-9223372036854775809"), NumberFault::kOutOfRange);
    EXPECT_EQ(integerFault("+99999999999999999999"), NumberFault::kOutOfRange);
    const IntegerRange index{0, 4294967295};
    EXPECT_EQ(parseInteger("0", index), 0);
    EXPECT_EQ(parseInteger("4294967295", index), 4294967295);
    EXPECT_EQ(integerFault("4294967296", index), NumberFault::kOutOfRange);
    EXPECT_EQ(integerFault("-1", index), NumberFault::kOutOfRange);
    const IntegerRange side{16, 8192};
    EXPECT_EQ(integerFault("15", side), NumberFault::kOutOfRange);
    EXPECT_EQ(parseInteger("16", side), 16);
    EXPECT_EQ(parseInteger("8192", side), 8192);
    EXPECT_EQ(integerFault("8193", side), NumberFault::kOutOfRange);
}

// ---- text ---------------------------------------------------------------------------------------

TEST(Trim, RemovesAsciiBlanksAtBothEndsOnly) {
    EXPECT_EQ(trim("  a b \t"), "a b");
    EXPECT_EQ(trim("\r\n\v\fx\f\v\n\r"), "x");
    EXPECT_EQ(trim("x"), "x");
    EXPECT_EQ(trim(""), "");
    EXPECT_EQ(trim(" \t \r\n"), "");
    // Not a blank: NUL and non-ASCII bytes stay.
    EXPECT_EQ(trim(std::string_view(" \0 ", 3)), std::string_view("\0", 1));
    EXPECT_EQ(trim("\xa0x\xa0"), "\xa0x\xa0");
}

TEST(AppendWords, SplitsAtRunsOfBlanksAndAppends) {
    std::vector<std::string_view> words = {"kept"};
    appendWords("  v 1.5\t-2 \r\n", words);
    EXPECT_EQ(words, (std::vector<std::string_view>{"kept", "v", "1.5", "-2"}));
    words.clear();
    appendWords("a\vb\fc", words);
    EXPECT_EQ(words, (std::vector<std::string_view>{"a", "b", "c"}));
    words.clear();
    appendWords(" \t ", words);
    appendWords("", words);
    EXPECT_TRUE(words.empty());
    // A NUL byte is part of a word.
    appendWords(std::string_view("x\0y z", 5), words);
    EXPECT_EQ(words, (std::vector<std::string_view>{std::string_view("x\0y", 3), "z"}));
}

TEST(QuoteForMessage, QuotesShortPrintableValuesAsTheyAre) {
    EXPECT_EQ(quoteForMessage(""), "''");
    EXPECT_EQ(quoteForMessage("abc 1.5"), "'abc 1.5'");
    EXPECT_EQ(quoteForMessage(std::string(kQuotedLimit, 'a')),
              "'" + std::string(kQuotedLimit, 'a') + "'");
}

TEST(QuoteForMessage, TruncatesAtTheLimitWithAnEllipsis) {
    EXPECT_EQ(kQuotedLimit, 60u);
    const std::string longValue = std::string(60, 'a') + "bcd";
    EXPECT_EQ(quoteForMessage(longValue), "'" + std::string(60, 'a') + "...'");
    EXPECT_EQ(quoteForMessage(std::string(61, 'z')), "'" + std::string(60, 'z') + "...'");
    // A megabyte stays a short message.
    EXPECT_EQ(quoteForMessage(std::string(1 << 20, 'q')).size(), 60u + 5u);
}

TEST(QuoteForMessage, WritesBytesOutsidePrintableAsciiInHex) {
    EXPECT_EQ(quoteForMessage(std::string("a\0b", 3)), "'a\\x00b'");
    EXPECT_EQ(quoteForMessage("tab\there"), "'tab\\x09here'");
    EXPECT_EQ(quoteForMessage("\x7f\xff"), "'\\x7f\\xff'");
    EXPECT_EQ(quoteForMessage("'"), "'''");
}

TEST(EqualsIgnoreCase, IgnoresTheCaseOfAsciiLettersOnly) {
    EXPECT_TRUE(equalsIgnoreCase("Solid", "sOLID"));
    EXPECT_TRUE(equalsIgnoreCase("", ""));
    EXPECT_TRUE(equalsIgnoreCase("a1_B", "A1_b"));
    EXPECT_FALSE(equalsIgnoreCase("solid", "solids"));
    EXPECT_FALSE(equalsIgnoreCase("solid", "so1id"));
    // '@' and '`' sit just before 'A' and 'a': no case of each other.
    EXPECT_FALSE(equalsIgnoreCase("@", "`"));
    EXPECT_FALSE(equalsIgnoreCase("\xc3\x89", "\xc3\xa9"));  // É and é: not ASCII
}

TEST(LowerExtension, LowersTheExtensionOnly) {
    EXPECT_EQ(lowerExtension("Model.OBJ"), ".obj");
    EXPECT_EQ(lowerExtension("dir.PLY/scene.Json"), ".json");
    EXPECT_EQ(lowerExtension("a.tar.GZ"), ".gz");
    EXPECT_EQ(lowerExtension("README"), "");
    EXPECT_EQ(lowerExtension("dir/.hidden"), "");
    EXPECT_EQ(lowerExtension("x.\xc3\x89"), ".\xc3\x89");  // non-ASCII bytes unchanged
}

// ---- files --------------------------------------------------------------------------------------

// A temporary directory per test (dir_) and write(name, bytes).
using ReadWholeFile = test::LoaderFiles;

TEST_F(ReadWholeFile, ReturnsEveryByteUntranslated) {
    std::string bytes = "line 1\r\nline 2\r";
    bytes += std::string("\0\xff\n", 3);
    bytes += std::string(200000, 'x');  // more than one read's buffer
    const fs::path p = write("a.bin", bytes);
    EXPECT_EQ(readWholeFile(p), bytes);
    const std::vector<unsigned char> asBytes = readWholeFileBytes(p);
    EXPECT_EQ(std::string(asBytes.begin(), asBytes.end()), bytes);
    EXPECT_EQ(readWholeFile(write("empty", "")), "");
}

TEST_F(ReadWholeFile, AMissingFileNamesTheFileAndTheSystemReason) {
    const fs::path missing = dir_ / "none.obj";
    try {
        readWholeFile(missing);
        ADD_FAILURE() << "no FileReadError";
    } catch (const FileReadError& e) {
        EXPECT_EQ(e.file, missing.string());
        EXPECT_EQ(e.reason, "No such file or directory");
        EXPECT_EQ(std::string(e.what()),
                  missing.string() + ": cannot read file: No such file or directory");
    }
    EXPECT_THROW(readWholeFileBytes(missing), FileReadError);
}

TEST_F(ReadWholeFile, ADirectoryIsRefusedWithTheSystemReason) {
    try {
        readWholeFile(dir_);
        ADD_FAILURE() << "no FileReadError";
    } catch (const FileReadError& e) {
        EXPECT_EQ(e.file, dir_.string());
        EXPECT_EQ(e.reason, "Is a directory");
    }
}

TEST_F(ReadWholeFile, SceneReadersGetASceneErrorWithTheSameWording) {
    const fs::path missing = dir_ / "gone.ply";
    try {
        readSceneFile(missing);
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file, missing.string());
        EXPECT_EQ(e.line, 0);
        EXPECT_EQ(e.message, "cannot read file: No such file or directory");
        EXPECT_EQ(std::string(e.what()),
                  missing.string() + ": cannot read file: No such file or directory");
    }
    EXPECT_EQ(readSceneFile(write("s.obj", "v 0 0 0\n")), "v 0 0 0\n");
}

}  // namespace
}  // namespace penumbra
