// Reading the bench's report.md back as a reader would: its Markdown tables by their header, and
// the conclusion at the top checked figure by figure against the tables below it (Table 1 and
// the error-against-time study), so that a conclusion computed apart from the tables, rounded
// otherwise or from another field shows up as a disagreement.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::test {

// The text from the line `heading` to the next heading of the same level or higher ("## " or
// "# "), or to the end.
inline std::string reportSection(const std::string& report, const std::string& heading) {
    const size_t at = report.find("\n" + heading + "\n");
    if (at == std::string::npos) return {};
    const size_t end = report.find("\n## ", at + 1);
    return report.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
}

// The cells of a Markdown table row "| a | b |", trimmed.
inline std::vector<std::string> tableCells(const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    for (size_t i = 1; i < line.size(); ++i) {
        if (line[i] != '|') {
            cell += line[i];
            continue;
        }
        const size_t b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
        cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
        cell.clear();
    }
    return cells;
}

// A Markdown table: its header and rows, cells by the header's column names.
struct ReportTable {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;

    // The cell of `column` in the row whose first cell is `first`; empty when there is none.
    std::string cell(const std::string& first, const std::string& column) const {
        size_t c = 0;
        while (c < header.size() && header[c] != column) ++c;
        for (const std::vector<std::string>& row : rows)
            if (!row.empty() && row[0] == first && c < row.size()) return row[c];
        return {};
    }
};

// The table whose header line starts with `headerStart` ("| scene | triangles |").
inline ReportTable reportTable(const std::string& report, const std::string& headerStart) {
    ReportTable t;
    const size_t at = report.find("\n" + headerStart);
    if (at == std::string::npos) return t;
    std::istringstream in(report.substr(at + 1));
    std::string line;
    std::getline(in, line);
    t.header = tableCells(line);
    std::getline(in, line);  // |---|
    while (std::getline(in, line) && line.rfind("|", 0) == 0) t.rows.push_back(tableCells(line));
    return t;
}

// Every figure of the report's conclusion ("## In short") compared with the table or sentence
// it comes from; the disagreements, each in words. `checked` counts the figures compared.
inline std::vector<std::string> conclusionAgainstTables(const std::string& report, int& checked) {
    std::vector<std::string> wrong;
    checked = 0;
    const std::string top = reportSection(report, "## In short");
    if (top.empty()) return {"no \"## In short\" section"};
    auto expectEqual = [&](const std::string& what, const std::string& inTop,
                           const std::string& inTable) {
        ++checked;
        if (inTop != inTable)
            wrong.push_back(what + ": \"" + inTop + "\" in the conclusion, \"" + inTable +
                            "\" in the table");
    };
    // Table 1: each scene's speed-up, faster or slower, and its share over the work limit.
    const ReportTable table1 = reportTable(report, "| scene | triangles | image |");
    const std::string speedupColumn = "speed-up (render only)";
    size_t withSpeedup = 0;
    for (const std::vector<std::string>& row : table1.rows)
        withSpeedup += table1.cell(row[0], speedupColumn) != "-";
    const std::regex sceneFigure(R"(([\w.-]+\.(?:json|obj)) (\d+\.\d+)(x|%))");
    const std::regex inverse(R"(^ \(sampling (\d+\.\d+)x faster\))");
    size_t listed = 0;
    std::istringstream lines(top);
    for (std::string line; std::getline(lines, line);) {
        const bool faster = line.rfind("- exact faster on ", 0) == 0;
        const bool slower = line.rfind("- exact slower on ", 0) == 0;
        if (faster || slower) {
            size_t n = 0, of = 0;
            std::sscanf(line.c_str() + 18, "%zu of %zu", &n, &of);
            listed += n;
            expectEqual("scenes", std::to_string(of), std::to_string(table1.rows.size()));
            size_t found = 0;
            for (std::sregex_iterator m(line.begin(), line.end(), sceneFigure), e; m != e; ++m) {
                ++found;
                const std::string scene = (*m)[1], figure = (*m)[2];
                const std::string cell = table1.cell(scene, speedupColumn);
                expectEqual(scene + " speed-up", figure + "x", cell.substr(0, cell.find(' ')));
                ++checked;
                if ((std::stod(figure) > 1) != faster)
                    wrong.push_back(scene + " " + figure + "x listed as " +
                                    (faster ? "faster" : "slower"));
                std::smatch inv;
                const std::string after = m->suffix();
                if (std::regex_search(after, inv, inverse)) {
                    ++checked;
                    const double s = std::stod(inv[1]), x = std::stod(figure);
                    if (std::fabs(s - 1 / x) > 0.005 + 0.005 / (x * x))
                        wrong.push_back(scene + ": sampling " + std::string(inv[1]) +
                                        "x faster is not the inverse of " + figure + "x");
                }
            }
            expectEqual(line.substr(0, 30) + "...: figures", std::to_string(n),
                        std::to_string(found));
        }
        if (line.rfind("- not all exact: ", 0) == 0)
            for (std::sregex_iterator m(line.begin(), line.end(), sceneFigure), e; m != e; ++m)
                expectEqual(std::string((*m)[1]) + " over the work limit",
                            std::string((*m)[2]) + "%",
                            table1.cell((*m)[1], "over the work limit"));
        // Sampling at equal error: each scene's speed-up and ray count against Table 1's.
        if (line.rfind("- at equal error (", 0) == 0) {
            const std::regex equalFigure(R"(([\w.-]+\.(?:json|obj)) (\d+\.\d+x) \((\d+) rays\))");
            for (std::sregex_iterator m(line.begin(), line.end(), equalFigure), e; m != e; ++m) {
                const std::string scene = (*m)[1];
                expectEqual(scene + " speed-up at equal error", (*m)[2],
                            table1.cell(scene, "exact's speed-up at equal error"));
                const std::string sampledCell =
                    table1.cell(scene, "sampled at equal error: rays per light, wall / CPU");
                expectEqual(scene + " rays at equal error", (*m)[3],
                            sampledCell.substr(0, sampledCell.find(' ')));
            }
        }
        if (line.rfind("- every evaluation exact", 0) == 0)
            for (const std::vector<std::string>& row : table1.rows) {
                const std::string cell = table1.cell(row[0], "over the work limit");
                expectEqual(row[0] + " over the work limit", "0.0%", cell == "-" ? "0.0%" : cell);
            }
    }
    expectEqual("scenes faster or slower", std::to_string(listed), std::to_string(withSpeedup));
    // The error-against-time study: the equal-error sentence and the table's rows.
    const std::string accuracy = reportSection(report, "## Error against time");
    const ReportTable curve = reportTable(report, "| method | rays per light |");
    const std::string exactSeconds = curve.cell("exact vs reference", "wall s");
    const std::string exactRmse = curve.cell("exact vs reference", "RMSE");
    std::smatch m;
    const std::regex equalError(
        R"(at about (\S+) rays per light and ([\d.]+) s wall, against ([\d.]+) s exact: exact ([\d.]+x))");
    if (std::regex_search(top, m, equalError)) {
        std::smatch t;
        const std::regex sentence(
            R"(at about (\S+) rays per light and ([\d.]+) s wall, against ([\d.]+) s for the exact method: ([\d.]+x))");
        if (!std::regex_search(accuracy, t, sentence)) {
            wrong.push_back("an equal-error figure at the top, no equal-error sentence below");
        } else {
            for (int i = 1; i <= 4; ++i) expectEqual("equal error", m[i], t[i]);
            expectEqual("exact seconds", m[3], exactSeconds);
        }
    }
    const std::regex equalTime(
        R"(sampling affords (\d+) rays? per light \(([\d.]+) s\), whose RMSE against the exact image, (\S+), is ([\d.]+)x the exact image's against the converged reference \((\S+)\))");
    if (std::regex_search(top, m, equalTime)) {
        std::string seconds, rmse;
        for (const std::vector<std::string>& row : curve.rows)
            if (row.size() > 4 && row[0] == "sampled vs exact" && row[1] == m[1]) {
                seconds = row[2];
                rmse = row[4];
            }
        expectEqual("equal time: seconds", m[2], seconds);
        expectEqual("equal time: RMSE", m[3], rmse);
        expectEqual("equal time: the exact image's RMSE", m[5], exactRmse);
        ++checked;
        const double ratio = std::stod(m[4]);
        const double expected = rmse.empty() ? NAN : std::stod(rmse) / std::stod(exactRmse);
        if (!(std::fabs(ratio - expected) <= 0.05 + expected * 2e-3))
            wrong.push_back("equal time: " + std::string(m[4]) + "x, the table's RMSEs give " +
                            std::to_string(expected));
    }
    return wrong;
}

}  // namespace penumbra::test
