// Tolerance files (compare/tolerance.h): what they accept, how they fail, and the verdict.
#include "compare/tolerance.h"

#include "compare/compare_test_util.h"

#include <gtest/gtest.h>

using namespace metamer;

namespace {

class CompareTolerance : public metamer::test::ScratchDir {
protected:
    // The message of the input error readTolerance throws for `text` (fails the test otherwise).
    std::string errorFor(const std::string& text) {
        std::filesystem::path p = write("tolerance.json", text);
        try {
            readTolerance(p);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::BadInput) << e.what();
            EXPECT_EQ(e.where().file, p.string()) << e.what();
            return e.what();
        }
        ADD_FAILURE() << "no error for " << text;
        return "";
    }
};

}  // namespace

TEST_F(CompareTolerance, TheExampleFileReadsEveryKey) {
    Tolerance t = readTolerance(std::string(METAMER_TEST_DATA_DIR) + "/compare/example_tolerance.json");
    EXPECT_EQ(t.maxRel, 1e-3);
    EXPECT_EQ(t.rmseRelative, 1e-4);
    EXPECT_EQ(t.spectralAngleMaxDeg, 0.05);
    EXPECT_EQ(t.fractionOverThreshold, 0.001);
    EXPECT_EQ(t.deltaE2000P95, 0.05);
    EXPECT_EQ(t.deltaE2000Max, 0.1);
    EXPECT_EQ(t.pixelThreshold, 1e-4);
    EXPECT_EQ(t.relativeFloor, 1e-4);
    EXPECT_FALSE(t.maxAbs);
    EXPECT_NE(t.description.find("float32"), std::string::npos);
    EXPECT_TRUE(t.wantsDeltaE());
    CompareOptions o;
    applyTolerance(t, o);
    EXPECT_EQ(o.pixelThreshold, 1e-4);
}

TEST_F(CompareTolerance, AnEmptyObjectChecksNothing) {
    Tolerance t = readTolerance(write("t.json", "{}"));
    CompareStats s;
    s.maxRel = 1e9;
    EXPECT_TRUE(judge(s, t).pass);
}

TEST_F(CompareTolerance, UnknownKeyNamesFileKeyLineAndSuggestion) {
    std::string m = errorFor("{\n  \"max_rel\": 1e-3,\n  \"rmse_relativ\": 1e-4\n}");
    EXPECT_NE(m.find(":3: rmse_relativ"), std::string::npos) << m;
    EXPECT_NE(m.find("did you mean 'rmse_relative'?"), std::string::npos) << m;
}

TEST_F(CompareTolerance, NegativeStringAndDuplicateValuesAreErrorsNamingTheKey) {
    std::string m = errorFor("{\"max_abs\": -0.5}");
    EXPECT_NE(m.find("max_abs"), std::string::npos) << m;
    EXPECT_NE(m.find("≥ 0"), std::string::npos) << m;
    m = errorFor("{\"delta_e2000_p95\": \"0.5\"}");
    EXPECT_NE(m.find("delta_e2000_p95"), std::string::npos) << m;
    EXPECT_NE(m.find("must be a number, not a string"), std::string::npos) << m;
    m = errorFor("{\"description\": 3}");
    EXPECT_NE(m.find("description: must be a string"), std::string::npos) << m;
    m = errorFor("{\"max_rel\": 1, \"max_rel\": 2}");
    EXPECT_NE(m.find("max_rel: duplicate key"), std::string::npos) << m;
    // A value beyond a double names its key and line (issue 30: it used to name only the file), and
    // a file nested 100 000 deep is refused, not a crash: the one JSON reader (core/json.h).
    m = errorFor("{\n  \"max_rel\": 1e-3,\n  \"max_abs\": 1e400\n}");
    EXPECT_NE(m.find("tolerance.json:3: max_abs: number 1e400 is out of the range of a double"), std::string::npos) << m;
    m = errorFor(std::string(100000, '[') + std::string(100000, ']'));
    EXPECT_NE(m.find("nests more than 64 levels"), std::string::npos) << m;
}

TEST_F(CompareTolerance, SyntaxErrorsAndNonObjectsNameTheFile) {
    std::string m = errorFor("{\n  \"max_rel\": 1e-3,\n}");
    EXPECT_NE(m.find("tolerance.json:3"), std::string::npos) << m;
    EXPECT_NE(m.find("JSON syntax error"), std::string::npos) << m;
    m = errorFor("[1, 2]");
    EXPECT_NE(m.find("not an array"), std::string::npos) << m;
    try {
        readTolerance(dir / "absent.json");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadInput);
        EXPECT_NE(std::string(e.what()).find("absent.json"), std::string::npos);
    }
}

TEST(CompareVerdict, ListsEveryFailedCriterionWithValueAndLimit) {
    CompareStats s;
    s.maxAbs = 0.5;
    s.rmseRelative = 2.1e-3;
    s.spectralAngleMaxDeg = 0.01;
    Tolerance t;
    t.maxAbs = 1.0;
    t.rmseRelative = 1e-3;
    t.spectralAngleMaxDeg = 0.01;  // equal is within
    t.deltaE2000P95 = 1.0;         // not computed: fails
    Verdict v = judge(s, t);
    EXPECT_FALSE(v.pass);
    ASSERT_EQ(v.failures.size(), 2u);
    EXPECT_EQ(v.failures[0], "rmse_relative 2.1e-03 > 1e-03");
    EXPECT_NE(v.failures[1].find("delta_e2000_p95 not computed"), std::string::npos) << v.failures[1];
    s.deltaE2000P95 = std::numeric_limits<double>::quiet_NaN();  // NaN never passes
    t.rmseRelative.reset();
    EXPECT_FALSE(judge(s, t).pass);
}

TEST(CompareVerdict, NumbersAreShortAndUnambiguous) {
    EXPECT_EQ(formatNumber(0.0), "0");
    EXPECT_EQ(formatNumber(2.1e-3), "2.1e-03");
    EXPECT_EQ(formatNumber(1e-3), "1e-03");
    EXPECT_EQ(formatNumber(0.5), "0.5");
    EXPECT_EQ(formatNumber(12.25), "12.25");
    EXPECT_EQ(formatNumber(std::numeric_limits<double>::infinity()), "inf");
}
