#include "core/csv_text.h"

#include <gtest/gtest.h>

using namespace metamer;

TEST(CsvText, QuotedFieldsSplitBackToThemselves) {
    EXPECT_EQ(csvQuoted("plain"), "plain");
    EXPECT_EQ(csvQuoted("a,b"), "\"a,b\"");
    EXPECT_EQ(csvQuoted("say \"hi\""), "\"say \"\"hi\"\"\"");
    const std::vector<std::string> fields = {"plain", "a,b", "say \"hi\"", "", "png,xyz"};
    std::string line;
    for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + csvQuoted(fields[i]);
    EXPECT_EQ(splitCsvRecord(line + "\r", Where{}), fields);
    EXPECT_THROW(splitCsvRecord("a,\"open", Where{"m.csv", "", 3}), Error);
}
