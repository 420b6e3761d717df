#include "app/progress_bar.h"

#include <unistd.h>

namespace vkrt {

ProgressBar::ProgressBar(std::string label, bool enabled, std::FILE* out, std::chrono::milliseconds lineEvery)
    : label_(std::move(label)),
      mode_(!enabled              ? Mode::Off
            : isatty(fileno(out)) ? Mode::Bar
                                  : Mode::Lines),
      out_(out),
      lineEvery_(lineEvery),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

void ProgressBar::update(uint64_t done, uint64_t total) {
    if (mode_ == Mode::Off || total == 0) return;
    const auto now = std::chrono::steady_clock::now();
    const double fraction = static_cast<double>(done) / static_cast<double>(total);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (mode_ == Mode::Lines) {
        // A line once `lineEvery` has passed since the last (or the start), none at the end: a short render
        // says nothing.
        if (done >= total || now - lastDraw_ < lineEvery_) return;
        lastDraw_ = now;
        std::fprintf(out_, "vkrt: %s %.1f%% after %.1f s, about %.1f s left\n", label_.c_str(),
                     100.0 * fraction, elapsed, eta);
        std::fflush(out_);
        return;
    }
    if (done < total && drawn_ && now - lastDraw_ < std::chrono::milliseconds(100)) return;
    lastDraw_ = now;
    drawn_ = true;
    constexpr int width = 30;
    const int filled = static_cast<int>(fraction * width);
    std::string bar(filled, '#');
    bar.append(width - filled, '.');
    std::fprintf(out_, "\r%s [%s] %5.1f%%  %.1fs elapsed, ETA %.1fs ", label_.c_str(), bar.c_str(),
                 100.0 * fraction, elapsed, eta);
    std::fflush(out_);
}

void ProgressBar::finish() {
    if (mode_ == Mode::Bar && drawn_) std::fprintf(out_, "\n");
    drawn_ = false;
}

}  // namespace vkrt
