// `metamer render`'s progress on stderr: strips, passes, frames or rows done, the time so far and an estimate of
// the time left, fed by the render job's progress hook (render/render_progress.h). On a terminal
// one line rewritten in place; elsewhere (--progress into a log) one line per step.
// Tests: tests/cli_test.cpp (CliProgress.*).
#pragma once

#include "render/render_progress.h"

#include <cstdio>

namespace metamer {

class ProgressLine {
public:
    // `terminal`: rewrite one line ('\r'); else append a line per step.
    ProgressLine(std::FILE* to, bool terminal) : to_(to), terminal_(terminal) {}
    ~ProgressLine();  // ends a line left open (a render stopped by an error)
    void operator()(const RenderProgress& p);

private:
    std::FILE* to_;
    bool terminal_;
    bool open_ = false;
    double startSeconds_ = 0;  // when the pixels began (done = 0): the estimate leaves the set-up out
};

}  // namespace metamer
