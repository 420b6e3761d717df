// The MPI job a vkrt process is one rank of. vkrt joins MPI only when it was built with MPI and a launcher
// started it (mpirun, mpiexec, srun: their environment says so); otherwise it is the one rank of a job of
// one, and nothing here calls MPI.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vkrt {

class MpiJob {
  public:
    // MPI_Init_thread (funneled: only the main thread calls MPI) when launched by an MPI launcher.
    MpiJob(int& argc, char**& argv);
    ~MpiJob();  // MPI_Finalize
    MpiJob(const MpiJob&) = delete;
    MpiJob& operator=(const MpiJob&) = delete;

    // Whether this vkrt was built with MPI.
    static bool built();

    int rank() const { return rank_; }
    int size() const { return size_; }
    // The rank among the ranks on this machine (MPI_COMM_TYPE_SHARED), which picks its GPU.
    int localRank() const { return localRank_; }
    // More than one rank: the ranks share one render.
    bool shared() const { return size_ > 1; }

    // Ends every rank of the job at once (MPI_Abort); the launcher exits non-zero. Without MPI: exit(code).
    [[noreturn]] void abort(int exitCode) const;
    void barrier() const;
    // A barrier that gives up once `flag` has been set for `graceSeconds` without every rank arriving: a rank
    // that died or aborted is never coming, and Open MPI tells the rest by SIGTERM, which sets the flag.
    // Returns whether every rank arrived.
    bool barrierUnlessAbandoned(const std::atomic<bool>& flag, double graceSeconds) const;
    // Whether `value` is true on any rank; every rank learns it.
    bool anyRank(bool value) const;
    // Rank 0's `value`, on every rank.
    bool fromRoot(bool value) const;
    double fromRoot(double value) const;
    // Element-wise sums of every rank's values, left in rank 0's (the others' are unchanged).
    void sumToRoot(double* values, size_t count) const;
    void sumToRoot(uint64_t* values, size_t count) const;
    // Every rank's text, in rank order, on rank 0 (empty elsewhere).
    std::vector<std::string> gatherToRoot(const std::string& text) const;

  private:
    bool initialized_ = false;
    int rank_ = 0;
    int size_ = 1;
    int localRank_ = 0;
};

// A counter on rank 0 that every rank adds to atomically, without rank 0 taking part (MPI-3 one-sided
// operations: MPI_Fetch_and_op in a passive-target epoch): the next sample index to hand out. Made and freed
// by every rank together; a counter not freed (an exception, a job whose other ranks are gone) is left to the
// end of the process, since freeing waits for every rank.
class SharedCounter {
  public:
    explicit SharedCounter(const MpiJob& job);
    ~SharedCounter();  // leaves the window as it is: see free()
    SharedCounter(const SharedCounter&) = delete;
    SharedCounter& operator=(const SharedCounter&) = delete;

    // Adds `amount` and returns the value before.
    uint64_t fetchAdd(uint64_t amount);
    // Sets the counter (rank 0, while no rank adds to it: between barriers).
    void set(uint64_t value);
    // Frees the window: every rank together.
    void free();

  private:
    struct Window;
    std::unique_ptr<Window> window_;
    uint64_t local_ = 0;  // the counter itself in a job of one
};

}  // namespace vkrt
