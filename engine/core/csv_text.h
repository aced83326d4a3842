// CSV text fields (RFC 4180 without line breaks inside fields): quoting a field for a CSV file
// that is written (bench rows, the batch index), and splitting one record of a file that is read
// (batch manifests). Spectral tables have their own numeric reader (spectral/csv.h).
// Tests: engine/core/csv_text_test.cpp.
#pragma once

#include "core/error.h"

#include <string>
#include <vector>

namespace metamer {

// `field` as it must appear in a CSV record: as is, or double-quoted with quotes doubled when it
// holds a comma, a quote or a line break.
std::string csvQuoted(const std::string& field);

// One record's fields, split at commas outside double quotes ("" inside quotes is a quote; a
// carriage return is dropped). An unclosed quote is an input error at `where`.
std::vector<std::string> splitCsvRecord(const std::string& line, const Where& where);

}  // namespace metamer
