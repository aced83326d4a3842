// What an error message shows of the user's input (core/error): a key path part or a quoted value
// of thousands of bytes is shortened with its length, control characters and bytes that are not
// UTF-8 are written as \xNN, so a message stays one readable line whatever a file holds.
#include "core/error.h"

#include <gtest/gtest.h>

using namespace metamer;

TEST(ErrorMessage, AKeyPathPartOfThousandsOfBytesIsShortenedWithItsLength) {
    const Where w{"scene.json", "materials." + std::string(3000, 'm') + ".diffuse", 12};
    EXPECT_EQ(w.str(), "scene.json:12: materials." + std::string(40, 'm') + "…(3000 bytes).diffuse");
    // A part of 80 bytes is kept whole; a cut never splits a UTF-8 character.
    EXPECT_EQ(Where({"f", std::string(80, 'k')}).str(), "f: " + std::string(80, 'k'));
    std::string wide;
    for (int i = 0; i < 60; ++i) wide += "λ";  // 2 bytes each: 120 bytes
    const std::string shown = Where({"f", wide}).str();
    EXPECT_EQ(shown, "f: " + wide.substr(0, 40) + "…(120 bytes)");
    const Error e(ExitCode::BadInput, w, "no spectrum 'x'");
    EXPECT_LT(std::string(e.what()).size(), 120u);
}

TEST(ErrorMessage, AQuotedValueOfThousandsOfBytesAndControlCharactersArePrintable) {
    const std::string m = printableMessage("no file '" + std::string(3000, 'u') + ".gltf' here\n\x01");
    EXPECT_EQ(m, "no file '" + std::string(60, 'u') + "…' (3005 bytes) here\\x0a\\x01");
}

// Outside quotes too (issue 51, class 10): a library's message naming a 5 000-byte URI, a list of
// long names — each long word keeps its first 60 bytes and its length, a list's comma after it.
TEST(ErrorMessage, ALongWordOutsideQuotesIsShortenedLikeAQuotedValue) {
    const std::string uri(5000, 'a');
    EXPECT_EQ(printableMessage("File not found : " + uri + " (tinygltf)"),
              "File not found : " + std::string(60, 'a') + "…(5000 bytes) (tinygltf)");
    const std::string name(300, 'm');
    EXPECT_EQ(printableMessage("the materials are grey, " + name + ", " + name + "; did you mean x?"),
              "the materials are grey, " + std::string(60, 'm') + "…(300 bytes), " + std::string(60, 'm') +
                  "…(300 bytes); did you mean x?");
    const std::string ordinary = "a line of short words, 'a quote', 160 bytes or less each";
    EXPECT_EQ(printableMessage(ordinary), ordinary);
}
