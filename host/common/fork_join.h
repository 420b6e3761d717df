// Fork-join for recursive work (a tree built top-down): two halves run at once while a thread budget
// lasts, otherwise one after the other on the calling thread.
#pragma once

#include <atomic>
#include <future>

namespace vkrt {

class ForkJoin {
  public:
    // At most `threads` threads at once, the one that starts the work included.
    explicit ForkJoin(unsigned threads) : budget_(static_cast<int>(threads)) {}

    // Runs `first` and `second`: `first` on a new thread and `second` on this one when `split` is asked
    // and the budget has a thread free, else `first` then `second` here. Exceptions reach the caller.
    template <typename First, typename Second>
    void invoke(bool split, First&& first, Second&& second) {
        if (!(split && claimThread())) {
            first();
            second();
            return;
        }
        auto firstTask = std::async(std::launch::async, [&] {
            struct Release {
                std::atomic<int>& busy;
                ~Release() { busy.fetch_sub(1); }
            } release{busy_};
            first();
        });
        second();
        firstTask.get();
    }

  private:
    bool claimThread() {
        int busy = busy_.load();
        while (busy < budget_) {
            if (busy_.compare_exchange_weak(busy, busy + 1)) return true;
        }
        return false;
    }

    int budget_;
    std::atomic<int> busy_{1};  // the calling thread
};

}  // namespace vkrt
