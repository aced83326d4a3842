#include "app/markdown_reference.h"

#include <fmt/format.h>

namespace metamer {

namespace {

// A table cell: no line breaks, '|' escaped.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '|') out += "\\|";
        else if (c == '\n') out += ' ';
        else out += c;
    }
    return out;
}

bool shown(const CLI::Option* o) { return !o->get_group().empty(); }

void writeOptions(const CLI::App& app, std::string& md) {
    std::string rows;
    for (const CLI::Option* o : app.get_options()) {
        if (!shown(o)) continue;
        // Every name as typed (get_name(false, true) would append a negated flag's "{false}").
        std::string names = o->get_positional() ? o->get_name(true) : "";
        for (const std::string& s : o->get_snames()) names += (names.empty() ? "-" : ", -") + s;
        for (const std::string& l : o->get_lnames()) names += (names.empty() ? "--" : ", --") + l;
        std::string value = o->get_type_name();
        if (o->get_items_expected_max() > 1 && !value.empty()) value += " …";
        std::string note;
        if (o->get_positional()) note = o->get_required() ? "required" : "optional";
        if (!o->get_default_str().empty()) note += (note.empty() ? "" : ", ") + ("`" + o->get_default_str() + "`");
        rows += fmt::format("| `{}` | {} | {} | {} |\n", cell(names), value.empty() ? "" : "`" + cell(value) + "`",
                            cell(note), cell(o->get_description()));
    }
    if (rows.empty()) return;
    md += "| argument | value | default | what it does |\n|---|---|---|---|\n" + rows;
}

}  // namespace

std::string markdownReference(const CLI::App& app) {
    std::string md = std::string(kReferenceBegin) + "\n\n";
    // Not app.get_name(): CLI11 names the app after argv[0], the path it was run by.
    md += app.get_description() + "\n\n";
    writeOptions(app, md);
    for (const CLI::App* sub : app.get_subcommands({})) {
        md += fmt::format("\n### metamer {}\n\n{}\n\n", sub->get_name(), sub->get_description());
        writeOptions(*sub, md);
    }
    md += "\n" + std::string(kReferenceEnd) + "\n";
    return md;
}

}  // namespace metamer
