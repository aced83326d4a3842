// The progress hook of a render job (RenderJob::progress): how far the pixels are, between units of
// work, for the CLI's progress line (app/progress_line.h), and for the Python binding's callbacks and
// Ctrl-C. Tests: tests/render_progress_test.cpp, tests/cli_test.cpp (CliProgress.*).
//
// The hook's contract:
// - It is called on the thread that called runRenderJob, never from a worker or the driver, and
//   never while a GPU submission is in flight.
// - First with done = 0, once the scene is loaded and every output is open (so `seconds` then is
//   the set-up's time), then as units finish, done rising to total. `unit` and `total` stay the
//   same within a job: "strip" for an image rendered in strips (over the memory budget), after
//   every strip; "pass" for whole GPU frames with the bands (total = --frames × the frame's
//   declared passes: depth pre-pass, lobe pass, band and transmission passes), after every pass,
//   each then a GPU submission of its own; "frame" for the display path without the bands (total =
//   --frames); "row" for the CPU reference (total = the image's rows), at most about 4 times a
//   second and at the end.
// - It may throw, any exception, to stop the render: runRenderJob stops drawing, removes every
//   temporary file it had opened and lets the exception through unchanged. No output file is
//   created or replaced (files of an earlier run under the same names stay as they were); a folder
//   that -o asked for may have been created, empty.
// - It should return quickly: it runs between units, so its time is the render's.
#pragma once

#include <functional>

namespace metamer {

struct RenderProgress {
    const char* unit = "frame";  // "strip", "pass", "frame" or "row"
    int done = 0, total = 1;
    double seconds = 0;  // since runRenderJob started (loading included)
};

using RenderProgressHook = std::function<void(const RenderProgress&)>;

}  // namespace metamer
