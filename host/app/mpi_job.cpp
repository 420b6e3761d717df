#include "app/mpi_job.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#ifdef VKRT_WITH_MPI
#include <mpi.h>
#endif

namespace vkrt {
namespace {

#ifdef VKRT_WITH_MPI
// Whether an MPI launcher started this process: Open MPI's mpirun, PMIx and PMI (MPICH's Hydra, Slurm).
bool launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
        if (std::getenv(name)) return true;
    }
    return false;
}

// MPI counts are ints: large buffers go in pieces of this many elements.
constexpr size_t kMaxElementsPerCall = size_t{1} << 28;

template <typename T>
void sumToRootInPieces(int rank, T* values, size_t count, MPI_Datatype type) {
    for (size_t first = 0; first < count; first += kMaxElementsPerCall) {
        const int n = static_cast<int>(std::min(kMaxElementsPerCall, count - first));
        if (rank == 0)
            MPI_Reduce(MPI_IN_PLACE, values + first, n, type, MPI_SUM, 0, MPI_COMM_WORLD);
        else
            MPI_Reduce(values + first, nullptr, n, type, MPI_SUM, 0, MPI_COMM_WORLD);
    }
}
#endif

}  // namespace

bool MpiJob::built() {
#ifdef VKRT_WITH_MPI
    return true;
#else
    return false;
#endif
}

MpiJob::MpiJob([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef VKRT_WITH_MPI
    if (!launchedByMpi()) return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    initialized_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local);
    MPI_Comm_rank(local, &localRank_);
    MPI_Comm_free(&local);
#endif
}

MpiJob::~MpiJob() {
#ifdef VKRT_WITH_MPI
    if (initialized_) MPI_Finalize();
#endif
}

void MpiJob::abort(int exitCode) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) MPI_Abort(MPI_COMM_WORLD, exitCode);
#endif
    std::exit(exitCode);
}

void MpiJob::barrier() const {
#ifdef VKRT_WITH_MPI
    if (initialized_) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

bool MpiJob::barrierUnlessAbandoned([[maybe_unused]] const std::atomic<bool>& flag,
                                    [[maybe_unused]] double graceSeconds) const {
#ifdef VKRT_WITH_MPI
    if (!initialized_) return true;
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    std::chrono::steady_clock::time_point flagged{};
    for (;;) {
        int arrived = 0;
        MPI_Test(&request, &arrived, MPI_STATUS_IGNORE);
        if (arrived) return true;
        const auto now = std::chrono::steady_clock::now();
        if (flag.load()) {
            if (flagged == std::chrono::steady_clock::time_point{}) flagged = now;
            if (std::chrono::duration<double>(now - flagged).count() >= graceSeconds) return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
#else
    return true;
#endif
}

bool MpiJob::anyRank(bool value) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) {
        int local = value ? 1 : 0, any = 0;
        MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
        return any != 0;
    }
#endif
    return value;
}

bool MpiJob::fromRoot(bool value) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) {
        int shared = value ? 1 : 0;
        MPI_Bcast(&shared, 1, MPI_INT, 0, MPI_COMM_WORLD);
        return shared != 0;
    }
#endif
    return value;
}

double MpiJob::fromRoot(double value) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) MPI_Bcast(&value, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
#endif
    return value;
}

void MpiJob::sumToRoot([[maybe_unused]] double* values, [[maybe_unused]] size_t count) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) sumToRootInPieces(rank_, values, count, MPI_DOUBLE);
#endif
}

void MpiJob::sumToRoot([[maybe_unused]] uint64_t* values, [[maybe_unused]] size_t count) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) sumToRootInPieces(rank_, values, count, MPI_UINT64_T);
#endif
}

std::vector<std::string> MpiJob::gatherToRoot(const std::string& text) const {
#ifdef VKRT_WITH_MPI
    if (initialized_) {
        // The lengths first, then the texts end to end.
        const int length = static_cast<int>(text.size());
        std::vector<int> lengths(rank_ == 0 ? size_ : 0);
        MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::vector<int> offsets(lengths.size());
        int total = 0;
        for (size_t i = 0; i < lengths.size(); ++i) {
            offsets[i] = total;
            total += lengths[i];
        }
        std::string all(static_cast<size_t>(total), '\0');
        MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                    MPI_COMM_WORLD);
        std::vector<std::string> texts;
        for (size_t i = 0; i < lengths.size(); ++i) texts.push_back(all.substr(offsets[i], lengths[i]));
        return texts;
    }
#endif
    return {text};
}

#ifdef VKRT_WITH_MPI
struct SharedCounter::Window {
    MPI_Win window = MPI_WIN_NULL;
    uint64_t* value = nullptr;  // rank 0's counter (unused elsewhere)
};
#else
struct SharedCounter::Window {};
#endif

SharedCounter::SharedCounter([[maybe_unused]] const MpiJob& job) {
#ifdef VKRT_WITH_MPI
    if (!job.shared()) return;
    window_ = std::make_unique<Window>();
    // One uint64_t on rank 0, none elsewhere; every rank holds a shared lock on all for the window's life.
    const MPI_Aint bytes = job.rank() == 0 ? sizeof(uint64_t) : 0;
    MPI_Win_allocate(bytes, sizeof(uint64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &window_->value,
                     &window_->window);
    if (job.rank() == 0) *window_->value = 0;
    MPI_Barrier(MPI_COMM_WORLD);  // the counter is zero before anyone adds to it
    MPI_Win_lock_all(0, window_->window);
#endif
}

SharedCounter::~SharedCounter() = default;

void SharedCounter::set(uint64_t value) {
#ifdef VKRT_WITH_MPI
    if (window_) {
        uint64_t before = 0;
        MPI_Fetch_and_op(&value, &before, MPI_UINT64_T, 0, 0, MPI_REPLACE, window_->window);
        MPI_Win_flush(0, window_->window);
        return;
    }
#endif
    local_ = value;
}

void SharedCounter::free() {
#ifdef VKRT_WITH_MPI
    if (!window_) return;
    MPI_Win_unlock_all(window_->window);
    MPI_Win_free(&window_->window);
    window_.reset();
#endif
}

uint64_t SharedCounter::fetchAdd(uint64_t amount) {
#ifdef VKRT_WITH_MPI
    if (window_) {
        uint64_t before = 0;
        MPI_Fetch_and_op(&amount, &before, MPI_UINT64_T, 0, 0, MPI_SUM, window_->window);
        MPI_Win_flush(0, window_->window);
        return before;
    }
#endif
    const uint64_t before = local_;
    local_ += amount;
    return before;
}

}  // namespace vkrt
