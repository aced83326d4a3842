// The CSV reader: what it accepts, and that every rejection is a metamer::Error naming the file
// and, where one line is at fault, that line. Fixtures in tests/data/spectral/.
#include "spectral/csv.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace metamer;
namespace fs = std::filesystem;

namespace {

fs::path dataFile(const std::string& name) {
    return fs::path(METAMER_TEST_DATA_DIR) / "spectral" / name;
}

// Reads `name` expecting an input error; returns its what() after checking that it names the
// file and, when line > 0, "file:line".
std::string expectInputError(const std::string& name, int line, size_t minColumns = 1) {
    fs::path path = dataFile(name);
    try {
        readSpectralTable(path, minColumns);
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_EQ(e.code(), ExitCode::BadInput) << what;
        EXPECT_NE(what.find(name), std::string::npos) << "message does not name the file: " << what;
        if (line > 0) {
            std::string at = name + ":" + std::to_string(line) + ":";
            EXPECT_NE(what.find(at), std::string::npos) << "expected '" << at << "' in: " << what;
            EXPECT_EQ(e.where().line, line) << what;
        }
        return what;
    }
    ADD_FAILURE() << name << " was accepted";
    return "";
}

}  // namespace

TEST(CsvReader, AcceptsHeaderCommentsAndBlankLines) {
    SpectralTable t = readSpectralTable(dataFile("comments_blank.csv"));
    ASSERT_EQ(t.wavelengths_nm.size(), 3u);
    EXPECT_EQ(t.wavelengths_nm[0], 400.0);
    EXPECT_EQ(t.wavelengths_nm[2], 600.0);
    ASSERT_EQ(t.columns.size(), 1u);
    EXPECT_EQ(t.columns[0][1], 0.5);  // spaces around fields are trimmed
    EXPECT_EQ(t.columnNames, std::vector<std::string>{"value"});
}

TEST(CsvReader, AcceptsFileWithoutHeader) {
    Spectrum s = readSpectrumCsv(dataFile("no_header.csv"));
    ASSERT_EQ(s.values.size(), 3u);
    EXPECT_EQ(s.values[2], 3.0);
    EXPECT_DOUBLE_EQ(s.at(475), 2.5);
    EXPECT_NE(s.source.find("no_header.csv"), std::string::npos);
}

TEST(CsvReader, AcceptsWindowsLineEnds) {
    Spectrum s = readSpectrumCsv(dataFile("crlf.csv"));
    ASSERT_EQ(s.values.size(), 2u);
    EXPECT_EQ(s.values[1], 1.5);
}

TEST(CsvReader, ReadsMultiColumnTableWithNames) {
    SpectralTable t = readSpectralTable(dataFile("three_columns.csv"), 3);
    ASSERT_EQ(t.columns.size(), 3u);
    EXPECT_EQ(t.columnNames, (std::vector<std::string>{"x_bar", "y_bar", "z_bar"}));
    EXPECT_EQ(t.columns[1][2], 0.8);
}

TEST(CsvErrors, MissingFile) {
    std::string what = expectInputError("does_not_exist.csv", 0);
    EXPECT_NE(what.find("not found"), std::string::npos) << what;
}

TEST(CsvErrors, EmptyFile) {
    std::string what = expectInputError("empty.csv", 0);
    EXPECT_NE(what.find("at least 2"), std::string::npos) << what;
}

TEST(CsvErrors, HeaderOnly) {
    std::string what = expectInputError("header_only.csv", 0);
    EXPECT_NE(what.find("found 0"), std::string::npos) << what;
}

TEST(CsvErrors, OneDataLine) {
    std::string what = expectInputError("one_line.csv", 0);
    EXPECT_NE(what.find("found 1"), std::string::npos) << what;
}

TEST(CsvErrors, NonNumericValueNamesLine) {
    std::string what = expectInputError("non_numeric.csv", 3);
    EXPECT_NE(what.find("abc"), std::string::npos) << what;
}

TEST(CsvErrors, NaNValueNamesLine) { expectInputError("nan.csv", 4); }

TEST(CsvErrors, InfiniteValueNamesLine) { expectInputError("inf.csv", 3); }

TEST(CsvErrors, NonMonotonicWavelengthsNameLine) {
    std::string what = expectInputError("non_monotonic.csv", 4);
    EXPECT_NE(what.find("increase"), std::string::npos) << what;
}

TEST(CsvErrors, DuplicatedWavelengthNamesLine) {
    std::string what = expectInputError("duplicate.csv", 4);
    EXPECT_NE(what.find("410"), std::string::npos) << what;
}

TEST(CsvErrors, RaggedColumnsNameLine) {
    std::string what = expectInputError("ragged.csv", 3);
    EXPECT_NE(what.find("column"), std::string::npos) << what;
}

TEST(CsvErrors, NegativeWavelengthNamesLine) { expectInputError("negative_wavelength.csv", 2); }

TEST(CsvErrors, TextAfterDataNamesLine) {
    std::string what = expectInputError("text_after_data.csv", 3);
    EXPECT_NE(what.find("end"), std::string::npos) << what;
}

TEST(CsvErrors, TooFewColumnsForTable) { expectInputError("no_header.csv", 1, 3); }

TEST(CsvErrors, SpectrumFileWithSeveralColumns) {
    try {
        readSpectrumCsv(dataFile("three_columns.csv"));
        FAIL() << "a three-column file was read as one spectrum";
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("three_columns.csv"), std::string::npos) << what;
        EXPECT_NE(what.find("one value column"), std::string::npos) << what;
    }
}
