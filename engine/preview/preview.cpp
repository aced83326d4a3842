#include "preview/preview.h"

#include "color/delta_e.h"
#include "core/error.h"
#include "core/statistics.h"
#include "core/timing.h"
#include "io/image_file.h"
#include "preview/camera_control.h"
#include "preview/display_bytes.h"
#include "preview/file_watch.h"
#include "preview/presenter.h"
#include "preview/settings_panel.h"
#include "preview/spectrum_plot.h"
#include "preview/ui_context.h"
#include "preview/view.h"
#include "preview/window.h"
#include "render/display_colour_space.h"
#include "render/render_setup.h"
#include "vk/context.h"

#include <imgui.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace metamer::preview {

namespace {

constexpr int kPanelWidth = 400;        // framebuffer pixels left of the images
constexpr int kMinWindowHeight = 720;   // room for the panel
constexpr int kProbeHeight = 330;       // the probe window, under the images
constexpr int kMinImagesWidth = 440;    // the probe window's least width
constexpr uint32_t kCursorColour = IM_COL32(255, 210, 60, 255);
constexpr uint32_t kPinColour = IM_COL32(80, 200, 255, 255);

struct ProbePoint {
    int view = 0;
    bool pinned = false;
    ProbeReadout readout;
};

class Session {
public:
    explicit Session(const PreviewOptions& options);
    PreviewReport run();

private:
    struct Region {
        int x, y, width, height;
    };
    Region region(size_t view) const;
    int imagesHeight() const;
    void layout();
    void handleImageInput();
    void drawControls();
    void drawProbes(const std::vector<ProbePoint>& probes);
    void drawMarkers();
    void renderViews();
    std::vector<ProbePoint> probes();
    void setCameraAll();
    void update(size_t view, const RenderJob& job);
    void setSplit(bool on);
    void reload();
    void save();
    void status(const std::string& message, bool error);
    void writeScreenshots(PreviewReport& report);

    PreviewOptions o_;
    bool scripted_;
    Window window_;
    std::unique_ptr<vk::Context> ctx_;
    std::vector<std::unique_ptr<View>> views_;
    std::unique_ptr<Presenter> presenter_;
    std::unique_ptr<UiContext> ui_;
    std::unique_ptr<SettingsPanel> panel_;
    std::unique_ptr<FileWatch> watch_;

    std::vector<std::vector<uint8_t>> bytes_;  // what each view shows, in the swapchain's byte order
    Camera camera_, fileCamera_;
    bool cameraMoved_ = false;
    bool needRender_ = true;
    bool dragging_ = false;
    int dragButton_ = 0;
    float dragDistance_ = 0.0f;
    std::optional<glm::ivec2> hover_, pin_;
    int editing_ = 0;
    bool watchFile_;
    bool markers_;
    std::string status_;
    bool statusError_ = false;
    // Last frame's figures, for the panel.
    double frame_ms_ = 0, shading_ms_ = 0, tonemap_ms_ = 0, probe_ms_ = 0, present_ms_ = 0;
    double rebuild_ms_ = 0;   // the last settings change or reload: scene, spectra, plan, GPU objects
    double excluded_ms_ = 0;  // this iteration's saving, reloading and rebuilding: not frame time
    std::vector<std::pair<std::filesystem::path, std::string>> written_;
};

Session::Session(const PreviewOptions& options)
    : o_(options),
      scripted_(options.frames > 0),
      window_(960, kMinWindowHeight, "metamer preview \u2014 " + options.job.scene.filename().string()),
      watchFile_(options.watch),
      markers_(options.frames == 0) {
    vk::ContextOptions co = jobContextOptions(o_.job);
    co.instanceExtensions = window_.requiredInstanceExtensions();
    co.createSurface = [this](VkInstance instance) { return window_.createSurface(instance); };
    ctx_ = std::make_unique<vk::Context>(co);
    views_.push_back(std::make_unique<View>(*ctx_, o_.job));
    if (!o_.split.empty()) views_.push_back(std::make_unique<View>(*ctx_, splitJob(o_.job, o_.split)));
    for (const auto& [pixel, flag] : {std::pair{o_.probe, "--probe"}, std::pair{o_.pin, "--pin"}})
        if (pixel && (pixel->x >= views_[0]->width() || pixel->y >= views_[0]->height()))
            failInput(Where{"", flag}, "pixel {},{} is outside the {}×{} image", pixel->x, pixel->y,
                      views_[0]->width(), views_[0]->height());
    camera_ = fileCamera_ = views_[0]->scene().camera;
    setCameraAll();
    layout();
    window_.show();
    presenter_ = std::make_unique<Presenter>(*ctx_, window_, scripted_);
    ui_ = std::make_unique<UiContext>(*ctx_, window_, presenter_->swapchain());
    panel_ = std::make_unique<SettingsPanel>(views_[0]->loaded().library);
    watch_ = std::make_unique<FileWatch>(o_.job.scene);
}

Session::Region Session::region(size_t view) const {
    int x = kPanelWidth;
    for (size_t i = 0; i < view; ++i) x += views_[i]->width();
    return {x, 0, views_[view]->width(), views_[view]->height()};
}

int Session::imagesHeight() const {
    int h = 0;
    for (const auto& v : views_) h = std::max(h, v->height());
    return h;
}

void Session::layout() {
    Region last = region(views_.size() - 1);
    int width = std::max(last.x + last.width, kPanelWidth + kMinImagesWidth);
    int height = std::max(kMinWindowHeight, imagesHeight() + kProbeHeight);
    float scale = window_.pixelScale();
    window_.resize(int(std::ceil(width / scale)), int(std::ceil(height / scale)));
    needRender_ = true;
}

void Session::setCameraAll() {
    for (auto& v : views_) v->setCamera(camera_);
    needRender_ = true;
}

void Session::status(const std::string& message, bool error) {
    status_ = message;
    statusError_ = error;
    std::fprintf(stderr, "metamer: %s\n", message.c_str());
}

void Session::update(size_t view, const RenderJob& job) {
    auto t0 = Clock::now();
    struct Exclude {
        Session& s;
        Clock::time_point t0;
        ~Exclude() {
            s.rebuild_ms_ = msSince(t0);
            s.excluded_ms_ += s.rebuild_ms_;
        }
    } exclude{*this, t0};
    try {
        int w = views_[view]->width(), h = views_[view]->height();
        views_[view]->update(job);
        views_[view]->setCamera(camera_);
        if (views_[view]->width() != w || views_[view]->height() != h) layout();
        needRender_ = true;
        status_.clear();
    } catch (const Error& e) {
        status(e.text(), true);  // the view keeps its settings and its image
    }
}

void Session::setSplit(bool on) {
    if (on && views_.size() == 1) {
        try {
            views_.push_back(std::make_unique<View>(*ctx_, splitJob(views_[0]->job(), o_.split)));
            views_.back()->setCamera(camera_);
        } catch (const Error& e) {
            status(e.text(), true);
            return;
        }
    } else if (!on && views_.size() == 2) {
        views_.pop_back();
        editing_ = 0;
    }
    layout();
}

void Session::reload() {
    auto t0 = Clock::now();
    bool failed = false;
    for (auto& v : views_) {
        try {
            v->reload();
        } catch (const Error& e) {
            status(std::string("reload: ") + e.text() + " (showing the last good version)", true);
            failed = true;
        }
    }
    if (!cameraMoved_) camera_ = views_[0]->scene().camera;  // the file's camera, as edited
    fileCamera_ = views_[0]->scene().camera;
    setCameraAll();
    layout();
    if (!failed) status("reloaded " + o_.job.scene.string() + (cameraMoved_ ? " (keeping the view)" : ""), false);
    rebuild_ms_ = msSince(t0);
    excluded_ms_ += rebuild_ms_;
}

void Session::save() {
    auto t0 = Clock::now();
    struct Exclude {
        Session& s;
        Clock::time_point t0;
        ~Exclude() { s.excluded_ms_ += msSince(t0); }
    } exclude{*this, t0};
    try {
        std::filesystem::create_directories(o_.outDir);
        std::string stem = o_.job.scene.stem().string() + "-preview";
        std::string all;
        for (size_t i = 0; i < views_.size(); ++i) {
            std::string name = stem + (views_.size() > 1 ? (i ? "-right" : "-left") : "");
            for (auto& w : views_[i]->save(o_.outDir / name)) {
                written_.push_back(w);
                all += (all.empty() ? "" : ", ") + w.first.string();
            }
        }
        status_ = "saved " + all;
        statusError_ = false;
    } catch (const Error& e) {
        status(e.text(), true);
    }
}

void Session::handleImageInput() {
    ImGuiIO& io = ImGui::GetIO();
    const float sx = io.DisplayFramebufferScale.x, sy = io.DisplayFramebufferScale.y;
    const glm::vec2 m(io.MousePos.x * sx, io.MousePos.y * sy);
    const bool free = !io.WantCaptureMouse;
    int over = -1;
    glm::ivec2 px(0);
    for (size_t i = 0; i < views_.size(); ++i) {
        Region r = region(i);
        if (m.x >= r.x && m.y >= r.y && m.x < r.x + r.width && m.y < r.y + r.height) {
            over = int(i);
            px = glm::ivec2(int(m.x) - r.x, int(m.y) - r.y);
        }
    }
    hover_.reset();
    if (free && over >= 0 && ImGui::IsMousePosValid()) hover_ = px;

    bool moved = false;
    if (!dragging_ && free && over >= 0 && (ImGui::IsMouseClicked(0) || ImGui::IsMouseClicked(1))) {
        dragging_ = true;
        dragButton_ = ImGui::IsMouseClicked(0) ? 0 : 1;
        dragDistance_ = 0.0f;
    }
    if (dragging_) {
        const float dx = io.MouseDelta.x * sx, dy = io.MouseDelta.y * sy;
        if (ImGui::IsMousePosValid() && (dx != 0.0f || dy != 0.0f)) {
            dragDistance_ += std::hypot(dx, dy);
            if (dragDistance_ >= 3.0f) {
                // Left: orbit (the scene turns with the mouse); right or shift+left: pan.
                if (dragButton_ == 1 || io.KeyShift) camera_ = pan(camera_, dx, dy);
                else camera_ = orbit(camera_, -0.01 * dx, 0.01 * dy);
                moved = true;
            }
        }
        if (!ImGui::IsMouseDown(dragButton_)) {
            // A left click that did not drag pins the probe there.
            if (dragButton_ == 0 && dragDistance_ < 3.0f && over >= 0) pin_ = px;
            dragging_ = false;
        }
    }
    if (free && over >= 0 && io.MouseWheel != 0.0f) {
        camera_ = zoom(camera_, std::pow(0.85, double(io.MouseWheel)));
        moved = true;
    }
    for (int key : window_.takeKeyPresses()) {
        if (io.WantCaptureKeyboard) continue;  // typing into a field
        if (key == GLFW_KEY_R) {
            camera_ = fileCamera_;
            cameraMoved_ = false;
            setCameraAll();
        }
        if (key == GLFW_KEY_U) pin_.reset();
        if (key == GLFW_KEY_S) save();
        if (key == GLFW_KEY_F5) reload();
        if (key == GLFW_KEY_ESCAPE) window_.requestClose();
    }
    if (moved) {
        cameraMoved_ = true;
        setCameraAll();
    }
}

void Session::drawControls() {
    const VkExtent2D ext = presenter_->swapchain().extent();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth) / ImGui::GetIO().DisplayFramebufferScale.x,
                                    float(ext.height) / ImGui::GetIO().DisplayFramebufferScale.y));
    ImGui::Begin("Metamer preview", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                                 ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
    const View& left = *views_[0];
    ImGui::TextWrapped("%s", o_.job.scene.string().c_str());
    ImGui::Text("%d\u00d7%d px, %d bands (%s nm)", left.width(), left.height(), left.scene().grid.bands(),
                left.scene().grid.str().c_str());
    ImGui::Text("frame %.1f ms", frame_ms_);
    if (rebuild_ms_ > 0) {
        ImGui::SameLine();
        ImGui::TextDisabled("(last rebuild %.0f ms)", rebuild_ms_);
    }
    ImGui::TextDisabled("shading %.1f  tonemap %.1f  probe %.1f  present %.1f ms", shading_ms_, tonemap_ms_, probe_ms_,
                        present_ms_);
    ImGui::TextDisabled("%s, present %s", ctx_->deviceInfo().name.c_str(), presenter_->swapchain().presentModeName());
    if (!status_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, statusError_ ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f) : ImVec4(0.6f, 0.9f, 0.6f, 1.0f));
        ImGui::TextWrapped("%s", status_.c_str());
        ImGui::PopStyleColor();
    }
    ImGui::Separator();

    bool split = views_.size() > 1;
    if (ImGui::Checkbox("Split view", &split)) setSplit(split);
    if (views_.size() > 1) {
        ImGui::SameLine();
        ImGui::RadioButton("edit left", &editing_, 0);
        ImGui::SameLine();
        ImGui::RadioButton("right", &editing_, 1);
        if (ImGui::SmallButton("copy left settings to the right")) update(1, views_[0]->job());
    }
    editing_ = std::min(editing_, int(views_.size()) - 1);
    RenderJob edited;
    if (panel_->draw(*views_[size_t(editing_)], edited)) update(size_t(editing_), edited);

    if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::TextDisabled("left drag: orbit   right or shift drag: pan");
        ImGui::TextDisabled("wheel: zoom   click: pin the probe");
        if (ImGui::Button("Reset view (R)")) {
            camera_ = fileCamera_;
            cameraMoved_ = false;
            setCameraAll();
        }
    }
    if (ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (ImGui::Button("Save cube and PNG (S)")) save();
        ImGui::SameLine();
        if (ImGui::Button("Reload (F5)")) reload();
        ImGui::Checkbox("reload when the scene file changes", &watchFile_);
        ImGui::TextDisabled("saves to %s/", o_.outDir.string().c_str());
    }
    ImGui::End();
}

std::vector<ProbePoint> Session::probes() {
    std::vector<ProbePoint> out;
    std::optional<glm::ivec2> cursor = hover_ ? hover_ : o_.probe;
    for (size_t i = 0; i < views_.size(); ++i) {
        View& v = *views_[i];
        auto inside = [&](const glm::ivec2& p) { return p.x >= 0 && p.y >= 0 && p.x < v.width() && p.y < v.height(); };
        if (cursor && inside(*cursor)) out.push_back({int(i), false, v.probe(cursor->x, cursor->y)});
        if (pin_ && inside(*pin_)) out.push_back({int(i), true, v.probe(pin_->x, pin_->y)});
    }
    return out;
}

void Session::drawProbes(const std::vector<ProbePoint>& probes) {
    const VkExtent2D ext = presenter_->swapchain().extent();
    const ImVec2 s = ImGui::GetIO().DisplayFramebufferScale;
    const int top = imagesHeight();
    ImGui::SetNextWindowPos(ImVec2(float(kPanelWidth) / s.x, float(top) / s.y));
    ImGui::SetNextWindowSize(ImVec2(std::max(1.0f, float(int(ext.width) - kPanelWidth) / s.x),
                                    std::max(1.0f, float(int(ext.height) - top) / s.y)));
    ImGui::Begin("Probe", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                       ImGuiWindowFlags_NoSavedSettings);
    if (probes.empty()) ImGui::TextDisabled("hover over the image for the probe; click to pin a second one");
    ImGui::SameLine();
    ImGui::TextDisabled("(XYZ as the detector sees it, white Y = 100, before adaptation)");
    if (pin_) {
        ImGui::SameLine();
        if (ImGui::SmallButton("Unpin (U)")) pin_.reset();
    }
    // One column per view: the spectra at the cursor and the pin, then their colours.
    if (!probes.empty() && ImGui::BeginTable("probes", int(views_.size()), ImGuiTableFlags_BordersInnerV)) {
        for (size_t vi = 0; vi < views_.size(); ++vi) {
            ImGui::TableNextColumn();
            std::vector<const ProbePoint*> mine;
            for (const auto& p : probes)
                if (p.view == int(vi)) mine.push_back(&p);
            if (views_.size() > 1) ImGui::Text(vi == 0 ? "left view" : "right view");
            if (mine.empty()) continue;
            const View& v = *views_[vi];
            const Representation& rep = v.loaded().representation;
            std::vector<PlotSeries> series;
            for (const ProbePoint* p : mine)
                series.push_back({fmt::format("{} {},{}", p->pinned ? "pin" : "cursor", p->readout.x, p->readout.y),
                                  p->readout.values, p->pinned ? kPinColour : kCursorColour});
            std::vector<double> x = mine[0]->readout.wavelengths_nm;
            if (x.empty())
                for (size_t c = 0; c < mine[0]->readout.values.size(); ++c) x.push_back(double(c));
            plotSpectra(vi == 0 ? "left" : "right", x, mine[0]->readout.channelNames, series,
                        rep.mode.spectral() ? "W\u00b7sr\u207b\u00b9\u00b7m\u207b\u00b2\u00b7nm\u207b\u00b9"
                                            : "(channel radiance)",
                        ImGui::GetContentRegionAvail().x, 120.0f);
            for (const ProbePoint* p : mine) {
                const ProbeReadout& r = p->readout;
                ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(p->pinned ? kPinColour : kCursorColour), "%s %d,%d",
                                   p->pinned ? "pin" : "cursor", r.x, r.y);
                if (r.colorimetric) {
                    ImGui::SameLine();
                    ImGui::Text(" XYZ %.2f %.2f %.2f", r.xyz.x, r.xyz.y, r.xyz.z);
                    ImGui::Text("   L*a*b* %.2f %.2f %.2f", r.lab.x, r.lab.y, r.lab.z);
                }
                ImGui::Text("   counts %d %d %d (%d-bit)%s", r.counts.x, r.counts.y, r.counts.z, r.bits,
                            r.clipped ? ", clipped" : "");
            }
            if (mine.size() == 2 && mine[0]->readout.colorimetric)
                ImGui::Text("\u0394E00 cursor\u2013pin: %.2f", deltaE2000(mine[0]->readout.lab, mine[1]->readout.lab));
        }
        ImGui::EndTable();
    }
    ImGui::End();
}

void Session::drawMarkers() {
    if (!markers_) return;
    ImDrawList* dl = ImGui::GetForegroundDrawList();
    const ImVec2 s = ImGui::GetIO().DisplayFramebufferScale;
    for (size_t i = 0; i < views_.size(); ++i) {
        Region r = region(i);
        auto at = [&](const glm::ivec2& p) { return ImVec2((r.x + p.x + 0.5f) / s.x, (r.y + p.y + 0.5f) / s.y); };
        if (pin_ && pin_->x < r.width && pin_->y < r.height) dl->AddCircle(at(*pin_), 6.0f, kPinColour, 16, 1.5f);
        if (hover_ && hover_->x < r.width && hover_->y < r.height) dl->AddCircle(at(*hover_), 4.0f, kCursorColour, 12, 1.0f);
    }
}

void Session::renderViews() {
    std::vector<ShownImage> shown;
    bytes_.resize(views_.size());
    double shading = 0, tonemap = 0;
    for (size_t i = 0; i < views_.size(); ++i) {
        View& v = *views_[i];
        v.render();
        shading += v.timings().shading_ms;
        tonemap += v.timings().tonemap_ms;
        bytes_[i] = toWindowBytes(v.image(), v.plan().display.bits, presenter_->swapchain().bgra());
        Region r = region(i);
        shown.push_back({r.x, r.y, r.width, r.height, &bytes_[i]});
    }
    presenter_->setImages(shown);
    shading_ms_ = shading;
    tonemap_ms_ = tonemap;
    needRender_ = false;
}

void Session::writeScreenshots(PreviewReport& report) {
    const bool bgra = presenter_->swapchain().bgra();
    // The screenshots hold the views' display counts as the window showed them: tagged with that
    // display's colour space when the views share one (render/display_colour_space.h).
    const DisplayModel& display = views_.front()->plan().display;
    const bool oneDisplay = std::all_of(views_.begin(), views_.end(), [&](const auto& v) {
        return v->plan().display.kind == display.kind && v->plan().display.name == display.name;
    });
    if (!oneDisplay) report.notes.push_back("the screenshots carry no colour space: the views show different displays");
    auto tag = [&](ImageFile& f) {
        if (oneDisplay) tagDisplayColourSpace(f, display);
    };
    if (!o_.screenshot.empty()) {
        Region last = region(views_.size() - 1);
        int W = last.x + last.width - kPanelWidth, H = 0;
        for (const auto& v : views_) H = std::max(H, v->height());
        std::vector<uint16_t> counts(size_t(W) * H * 3, 0);
        const VkExtent2D fe = presenter_->lastFrameExtent();
        bool fromFrame = presenter_->lastFrameRead();
        for (size_t i = 0; i < views_.size() && fromFrame; ++i) {
            Region r = region(i);
            fromFrame = r.x + r.width <= int(fe.width) && r.y + r.height <= int(fe.height);
        }
        if (!fromFrame)
            report.notes.push_back(fmt::format(
                "the screenshot comes from the display images handed to the window, not from the presented frame "
                "({})", presenter_->lastFrameRead() ? "the window is too small to show the whole view"
                                                    : "this swapchain's images cannot be read back"));
        for (size_t i = 0; i < views_.size(); ++i) {
            Region r = region(i);
            std::vector<uint16_t> part =
                fromFrame ? fromWindowBytes(presenter_->lastFrame(), int(fe.width), int(fe.height), bgra, r.x, r.y,
                                            r.width, r.height)
                          : fromWindowBytes(bytes_[i], r.width, r.height, bgra, 0, 0, r.width, r.height);
            for (int y = 0; y < r.height; ++y)
                std::copy_n(&part[size_t(y) * r.width * 3], size_t(r.width) * 3,
                            &counts[(size_t(y) * W + (r.x - kPanelWidth)) * 3]);
        }
        ImageFile f{W, H, {"R", "G", "B"}, {}};
        std::string what = views_.size() > 1 ? "left and right views side by side" : "the view";
        f.attributes.push_back({"ImageDescription", "metamer preview screenshot: " + what});
        tag(f);
        writeImage(o_.screenshot, f, counts, 8);
        report.written.push_back({o_.screenshot, fmt::format("{}×{} px, 8-bit display counts as the window showed {}{}",
                                                             W, H, what, fromFrame ? "" : " (from the display images)")});
    }
    if (!o_.windowScreenshot.empty()) {
        if (!presenter_->lastFrameRead()) {
            report.notes.push_back("no window screenshot: this swapchain's images cannot be read back");
        } else {
            const VkExtent2D fe = presenter_->lastFrameExtent();
            std::vector<uint16_t> all = fromWindowBytes(presenter_->lastFrame(), int(fe.width), int(fe.height), bgra, 0,
                                                        0, int(fe.width), int(fe.height));
            ImageFile f{int(fe.width), int(fe.height), {"R", "G", "B"}, {}};
            tag(f);
            writeImage(o_.windowScreenshot, f, all, 8);
            report.written.push_back({o_.windowScreenshot, fmt::format("{}×{} px, the whole window, UI included",
                                                                       fe.width, fe.height)});
        }
    }
}

PreviewReport Session::run() {
    PreviewReport report;
    report.device = ctx_->deviceInfo().name;
    report.presentMode = presenter_->swapchain().presentModeName();
    report.width = views_[0]->width();
    report.height = views_[0]->height();
    report.bands = views_[0]->scene().grid.bands();
    for (const auto& v : views_) report.build_ms += v->timings().build_ms;
    if (o_.pin) pin_ = o_.pin;
    if (o_.job.verbose)
        std::fprintf(stderr, "metamer: preview window open (%s)%s\n", report.device.c_str(),
                     watchFile_ ? fmt::format("; watching {}", o_.job.scene.string()).c_str() : "");

    std::vector<double> frames, shading, tonemap, probe, present;
    std::vector<ProbePoint> lastPoints;
    int shown = 0, attempts = 0;
    while (scripted_ ? shown < o_.frames : !window_.closeRequested()) {
        if (scripted_ && ++attempts > o_.frames + 100)
            failRuntime("preview: the window presented {} of {} frames (the swapchain kept going out of date)", shown,
                        o_.frames);
        if (scripted_ || needRender_ || dragging_) glfwPollEvents();
        else glfwWaitEventsTimeout(0.25);
        auto t0 = Clock::now();
        excluded_ms_ = 0;
        if (watchFile_ && watch_->changed()) reload();

        ui_->newFrame();
        if (!scripted_) handleImageInput();
        drawControls();
        bool rendered = needRender_ || scripted_;
        if (rendered) renderViews();
        auto tp = Clock::now();
        std::vector<ProbePoint> points = probes();
        double probeMs = msSince(tp);
        drawProbes(points);
        drawMarkers();
        ui_->endFrame();

        // Screenshots are of the last frame: in a scripted run that is known; in an interactive
        // one every frame is read back, so the frame shown when the window closes is at hand.
        const bool last = scripted_ && shown == o_.frames - 1;
        const bool screenshots = !o_.screenshot.empty() || !o_.windowScreenshot.empty();
        const bool readBack = screenshots && (last || !scripted_);
        auto tq = Clock::now();
        if (!presenter_->frame([&](VkCommandBuffer cmd) { ui_->record(cmd); }, readBack)) {
            if (!scripted_) glfwWaitEventsTimeout(0.05);  // minimized, or the swapchain was remade
            continue;
        }
        const double presentMs = msSince(tq);
        // The panel's figures are those of the last frame that rendered (an idle frame only
        // redraws the panels); saving, reloading and rebuilding are not frame time.
        if (rendered) {
            probe_ms_ = probeMs;
            present_ms_ = presentMs;
            frame_ms_ = msSince(t0) - excluded_ms_;
            frames.push_back(frame_ms_);
            shading.push_back(shading_ms_);
            tonemap.push_back(tonemap_ms_);
            probe.push_back(probe_ms_);
            present.push_back(present_ms_);
        }
        lastPoints = std::move(points);
        ++shown;
    }
    // The settings, probes and screenshots of the last frame shown.
    for (size_t i = 0; i < views_.size(); ++i)
        report.views += fmt::format("{}{}: {}", i ? "; " : "", views_.size() > 1 ? (i ? "right" : "left") : "view",
                                    views_[i]->plan().description);
    for (const auto& p : lastPoints)
        report.probes.push_back((views_.size() > 1 ? (p.view ? "right " : "left ") : std::string()) +
                                (p.pinned ? "pin " : "") + describeProbe(p.readout));
    for (size_t i = 0; i < views_.size(); ++i) {
        const ProbePoint *c = nullptr, *q = nullptr;
        for (const auto& p : lastPoints)
            if (p.view == int(i)) (p.pinned ? q : c) = &p;
        if (c && q && c->readout.colorimetric)
            report.probes.push_back(fmt::format("{}ΔE00 probe–pin {:.3f}", views_.size() > 1 ? (i ? "right " : "left ") : "",
                                                deltaE2000(c->readout.lab, q->readout.lab)));
    }
    if (shown > 0) writeScreenshots(report);
    if (o_.saveAtEnd) save();
    report.written.insert(report.written.end(), written_.begin(), written_.end());
    report.frames = int(frames.size());
    if (!frames.empty()) {
        report.first_ms = frames[0];
        auto rest = [](const std::vector<double>& v) { return std::vector<double>(v.begin() + (v.size() > 1), v.end()); };
        report.median_ms = median(rest(frames));
        report.medianShading_ms = median(rest(shading));
        report.medianTonemap_ms = median(rest(tonemap));
        report.medianProbe_ms = median(rest(probe));
        report.medianPresent_ms = median(rest(present));
    }
    return report;
}

}  // namespace

RenderJob splitJob(const RenderJob& left, const std::vector<std::string>& split) {
    RenderJob job = left;
    for (const auto& s : split) {
        auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            failInput(Where{"", "--split"}, "'{}' is not SETTING=VALUE (e.g. lights.0.spectrum=illuminants/A, "
                      "detector=cie1964)", s);
        std::string key = s.substr(0, eq), value = s.substr(eq + 1);
        if (key == "detector") job.detector = value;
        else if (key == "adapt" || key == "adaptation") job.adaptation = value;
        else if (key == "display") job.display = value;
        else if (key == "mode") job.mode = value;
        else if (key == "grid") job.grid = Grid::parse(value, Where{"", "--split grid"});
        else setOverride(job.overrides, key, value);
    }
    return job;
}

glm::ivec2 parsePixel(const std::string& text, const std::string& flag) {
    int x = 0, y = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &tail) != 2 || x < 0 || y < 0)
        failInput(Where{"", flag}, "'{}' is not a pixel X,Y (two whole numbers ≥ 0, row 0 at the top)", text);
    return {x, y};
}

PreviewReport runPreview(const PreviewOptions& options) {
    if (options.frames < 0) failInput(Where{"", "--frames"}, "must be ≥ 0, got {}", options.frames);
    PreviewReport report;
    {
        Session session(options);
        report = session.run();
    }  // every Vulkan object destroyed: the layers report leaks now
    report.validationErrors = vk::Context::validationErrorsAtExit();
    return report;
}

}  // namespace metamer::preview
