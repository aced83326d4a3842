#include "core/json.h"

#include "core/error.h"

#include <algorithm>
#include <set>
#include <vector>

namespace metamer {

namespace {

// ---------------------------------------------------------------------------------------------
// Parsing: nlohmann's parser reports syntax errors by byte offset and ignores duplicate keys, so
// a SAX handler follows the key path as it parses, to reject duplicates and to say where an error
// happened, and hands every event on to nlohmann's own DOM builder. (Its callback parser would do
// the same, but scans a container's elements at every object's end: 200 000 objects took 11 s.)

using Json = nlohmann::ordered_json;

class PathTracker {
public:
    PathTracker(std::string file, Json& result) : file_(std::move(file)), dom_(result) {}

    // The key path being parsed; its first `levels` parts when given (a path 64 levels deep is
    // mostly noise).
    std::string path(size_t levels = SIZE_MAX) const {
        std::string p;
        for (const auto& f : stack_) {
            if (levels-- == 0) return p + ".…";
            std::string part = f.array ? std::to_string(f.count) : f.key;
            if (part.empty()) break;
            p += (p.empty() ? "" : ".") + part;
        }
        return p;
    }

    // nlohmann's SAX interface.
    bool null() { return value(dom_.null()); }
    bool boolean(bool v) { return value(dom_.boolean(v)); }
    bool number_integer(Json::number_integer_t v) { return value(dom_.number_integer(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(dom_.number_unsigned(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t& text) { return value(dom_.number_float(v, text)); }
    bool string(Json::string_t& v) { return value(dom_.string(v)); }
    bool binary(Json::binary_t& v) { return value(dom_.binary(v)); }
    bool start_object(std::size_t n) { return open(false) && dom_.start_object(n); }
    bool start_array(std::size_t n) { return open(true) && dom_.start_array(n); }
    bool key(Json::string_t& k) {
        Frame& f = stack_.back();
        f.key = k;
        if (!f.keys.insert(f.key).second)
            failInput(Where{file_, path()}, "duplicate key (the later value would silently replace the earlier)");
        return dom_.key(k);
    }
    bool end_object() { return close() && dom_.end_object(); }
    bool end_array() { return close() && dom_.end_array(); }
    template <typename Exception>
    bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
        return dom_.parse_error(position, token, e);  // throws e
    }

private:
    static constexpr size_t kShownDepth = 6;

    struct Frame {
        bool array = false;
        std::string key;  // the member being parsed; "" between members
        size_t count = 0;  // elements completed so far = index of the one being parsed
        std::set<std::string> keys;
    };

    bool open(bool array) {
        if (stack_.size() >= size_t(kMaxJsonDepth))
            failInput(Where{file_, path(kShownDepth)}, "the JSON nests more than {} levels deep", kMaxJsonDepth);
        stack_.push_back({array});
        return true;
    }
    bool close() {
        stack_.pop_back();
        finishValue();
        return true;
    }
    bool value(bool ok) {
        finishValue();
        return ok;
    }
    void finishValue() {
        if (stack_.empty()) return;
        if (stack_.back().array)
            ++stack_.back().count;
        else
            stack_.back().key.clear();
    }

    std::string file_;
    std::vector<Frame> stack_;
    nlohmann::detail::json_sax_dom_parser<Json> dom_;
};

// 1-based line and column of a 0-based byte offset.
std::pair<int, int> lineColumn(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    int line = 1;
    size_t lineStart = 0;
    for (size_t i = 0; i < offset; ++i)
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    return {line, static_cast<int>(offset - lineStart) + 1};
}

// A file saved as UTF-16 (a byte-order mark, or a NUL in every other byte of its start) is named
// as such, rather than as a syntax error at column 1.
void refuseUtf16(const std::string& text, const std::string& file) {
    const bool bom = text.size() >= 2 && ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF'));
    const size_t head = std::min<size_t>(text.size(), 64);
    size_t nuls = 0;
    for (size_t i = 0; i < head; ++i) nuls += text[i] == '\0';
    if (bom || (head >= 4 && nuls * 3 >= head))
        failInput(Where{file}, "is not UTF-8: it looks like UTF-16{} (save it as UTF-8)",
                  bom ? " (it starts with a UTF-16 byte-order mark)" : "");
}

}  // namespace

nlohmann::ordered_json parseJson(const std::string& text, const std::string& file) {
    refuseUtf16(text, file);
    nlohmann::ordered_json result;
    PathTracker tracker(file, result);
    try {
        Json::sax_parse(text, &tracker, nlohmann::json::input_format_t::json, /*strict=*/true,
                        /*ignore_comments=*/false);
        return result;
    } catch (const nlohmann::json::parse_error& e) {
        // nlohmann's message reads "[json.exception.parse_error.101] parse error at line L,
        // column C: what"; keep only "what" and compute the position ourselves.
        std::string what = e.what();
        if (size_t c = what.find("column "); c != std::string::npos)
            if (size_t colon = what.find(": ", c); colon != std::string::npos) what = what.substr(colon + 2);
        auto [line, column] = lineColumn(text, e.byte == 0 ? 0 : e.byte - 1);
        failInput(Where{file, tracker.path(), line}, "JSON syntax error at column {}: {}", column, what);
    } catch (const nlohmann::json::out_of_range& e) {
        // A number too large for a double (1e999). Find the literal for the line number.
        std::string what = e.what();
        std::string literal;
        if (size_t q = what.find('\''); q != std::string::npos) {
            size_t q2 = what.find('\'', q + 1);
            if (q2 != std::string::npos) literal = what.substr(q + 1, q2 - q - 1);
        }
        int line = 0;
        if (!literal.empty())
            if (size_t at = text.find(literal); at != std::string::npos) line = lineColumn(text, at).first;
        failInput(Where{file, tracker.path(), line}, "number {} is out of the range of a double", literal);
    }
}


}  // namespace metamer
