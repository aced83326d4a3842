#include "app/progress_line.h"

#include <fmt/format.h>

#include <string>

namespace metamer {

namespace {

std::string duration(double seconds) {
    if (seconds < 60) return fmt::format("{:.1f} s", seconds);
    const int s = int(seconds + 0.5);
    return s < 3600 ? fmt::format("{}:{:02d} min", s / 60, s % 60) : fmt::format("{}:{:02d} h", s / 3600, s / 60 % 60);
}

}  // namespace

ProgressLine::~ProgressLine() {
    if (open_) std::fputc('\n', to_);
}

void ProgressLine::operator()(const RenderProgress& p) {
    std::string line;
    if (p.done == 0) {
        startSeconds_ = p.seconds;
        const std::string unit = p.unit;
        const char* plural = p.total == 1 ? "" : unit.back() == 's' ? "es" : "s";  // "passes"
        line = fmt::format("metamer: rendering: {} {}{} (set-up {})", p.total, unit, plural, duration(p.seconds));
    } else {
        // The time per unit so far, times the units left: strips and frames cost about the same.
        const double perUnit = (p.seconds - startSeconds_) / p.done;
        line = fmt::format("metamer: {} {} of {}, {} elapsed", p.unit, p.done, p.total, duration(p.seconds));
        if (p.done < p.total) line += fmt::format(", about {} left", duration(perUnit * (p.total - p.done)));
    }
    if (terminal_) {
        std::fprintf(to_, "\r\033[K%s", line.c_str());  // \033[K: clear what a longer line left
        open_ = p.done < p.total;
        if (!open_) std::fputc('\n', to_);
    } else {
        std::fprintf(to_, "%s\n", line.c_str());
    }
    std::fflush(to_);
}

}  // namespace metamer
