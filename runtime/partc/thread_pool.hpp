// partc/thread_pool.hpp: ThreadPool, the threads behind partc::parallel_for
// (parallel.hpp), in place of OpenMP's parallel regions.
//
//   detail::ThreadPool::instance().run(threads, chunks, f);  // f(c) for c < chunks
//
// Why not OpenMP: libgomp's workers and its end-of-region barrier spin for a
// long time (GOMP_SPINCOUNT, 300000 rounds by default) before they sleep, and
// every thread of a team must arrive at that barrier. When another program
// keeps a core busy, the thread that is not running holds the others up, and
// they spin away the very time slices it needs: a DEM model took 71 s on 2
// threads against 0.48 s on one. OMP_WAIT_POLICY=passive cures it, but libgomp
// reads the environment when it is loaded, before main or any constructor of
// the program (setenv there is too late), and has no call to change it later.
//
// How this pool behaves instead:
// - The calling thread works too, and nobody waits for anybody to arrive.
//   The chunks of a job are dealt out in one share per thread; each thread
//   claims its own share's chunks one at a time, then what is left of the
//   others'. If a worker is descheduled, the caller does its share; the
//   caller waits only for chunks that a worker has claimed and not finished.
// - Waits spin briefly (spin_wait), then sleep on a condition variable, so
//   that a thread preempted mid-chunk can be run on the waiter's core, and
//   an idle worker leaves its core to whatever else the machine runs.
// - Which thread runs which chunk varies from run to run. parallel_for's
//   callers never depend on it: every iteration writes its own values only,
//   so results are bitwise the same for any thread count and any schedule.
// - Workers are started when first needed and live as long as the process:
//   the pool is never destroyed, so no static destructor can run after it is
//   gone, and nothing has to be joined at exit (sleeping threads just end).
// - One job at a time: a run that finds the pool busy (a call from another
//   thread, or from inside a job: nested loops) returns false and the caller
//   runs its loop serially. A child made by fork() starts a pool of its own.
// - An exception thrown by f is rethrown by run on the calling thread, once
//   every claimed chunk has ended; chunks not yet started are skipped.
// - All but run's forwarding to run_erased is compiled once, in the runtime
//   library (thread_pool.cpp), which also holds the one pool of the process.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>

namespace partc::detail {

// One round of a spin loop: tells the CPU (and a hypervisor) that we wait.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

class ThreadPool {
 public:
  // Most threads in one job, the caller included.
  static constexpr unsigned max_threads = 256;
  // Most chunks in one job (a share word has 16 bits for a chunk index).
  static constexpr std::size_t max_chunks = 0xffff;
  // How long a waiting thread spins before it sleeps: a worker for the next
  // job, the caller for chunks still running. Long enough to cover the gap
  // between the loops of one kernel (a pair walk's two phases, the particle
  // loop after it), short against a step's serial work (a cell-list build).
  // 0, 5, 20, 50, 100 and 200 us were tried (tests/bench/bench_loaded, 2
  // cores, md at N = 500 and 2000, DEM at 3000): none collapsed beside busy
  // loops, and the differences were within the machine's noise (~15%).
  static constexpr std::chrono::microseconds spin_wait{20};

  static ThreadPool& instance() { return *current(); }

  // f(c) for every chunk c in [0, chunks), on the calling thread and at most
  // threads - 1 workers; returns once all have run (true), or at once (false)
  // when the pool is busy, without running any.
  template <class F>
  bool run(unsigned threads, std::size_t chunks, F& f) {
    return run_erased(
        threads, chunks, [](void* context, std::size_t c) { (*static_cast<F*>(context))(c); }, &f);
  }

  // Workers started so far.
  unsigned worker_count() const { return started_.load(std::memory_order_relaxed); }

 private:
  using Task = void (*)(void* context, std::size_t chunk);

  // The chunks of a job are dealt into one share per thread, consecutive
  // chunks each. A thread takes the chunks of its own share from the front,
  // then those left in the others' from the back, so that two threads touch
  // the same cache line only when one has run out of its own work (on the
  // 2-core machine of tests/bench, handing a cache line to the other core
  // costs ~200 ns, as much as ~50 iterations of a light loop).
  //
  // A share word: job generation (32 bits) | front (16) | back (16); chunks
  // front .. back - 1 are unclaimed. A chunk is claimed by one compare-exchange
  // on the whole word, so a thread that read an older job's word can never
  // claim a chunk of a newer one (the generation would have to wrap around
  // 2^32 jobs between its load and its compare-exchange).
  static std::uint32_t generation(std::uint64_t word) {
    return static_cast<std::uint32_t>(word >> 32);
  }
  static std::size_t front(std::uint64_t word) { return (word >> 16) & 0xffffu; }
  static std::size_t back(std::uint64_t word) { return word & 0xffffu; }
  static std::uint64_t share_word(std::uint32_t job, std::size_t front, std::size_t back) {
    return std::uint64_t{job} << 32 | std::uint64_t{front} << 16 | std::uint64_t{back};
  }

  // Each on a cache line of its own.
  struct alignas(64) Share {
    std::atomic<std::uint64_t> word{0};
  };
  struct alignas(64) Job {
    // generation (32 bits) | threads taking part (32): what workers wait on.
    std::atomic<std::uint64_t> word{0};
    // Written before word (under dispatch_), read after a claim: a claimed
    // chunk keeps the job from ending, so they stay as published.
    Task task = nullptr;
    void* context = nullptr;
    std::size_t chunks = 0;
    std::atomic<bool> failed{false};
  };
  struct alignas(64) Done {
    std::atomic<std::size_t> chunks{0};  // chunks of the job finished
    std::atomic<bool> caller_sleeps{false};
  };

  ThreadPool() = default;

  // Never destroyed (see above). A forked child gets a pool of its own: it
  // has none of the parent's workers, and may have copied a mutex that one
  // of them held.
  static ThreadPool*& current();

  static bool& inside_job();

  bool run_erased(unsigned threads, std::size_t chunks, Task task, void* context);

  // Starts workers until there are at least `count` (fewer if the system
  // refuses); returns how many of them, at most `count`, a job can have.
  unsigned start_workers(std::size_t count);

  // Claims a chunk of share k of the job: from the front (the share's own
  // thread) or the back (another); the chunk, or none (-1).
  std::ptrdiff_t claim(unsigned k, std::uint32_t job, bool own);

  // Thread `self` (0: the caller) runs chunks of the job until none is left
  // unclaimed: its own share's, then the others'.
  void work(unsigned self, std::uint32_t job, unsigned threads);

  // pred() within spin_wait of spinning, or false. Between rounds the thread
  // yields: if the thread it waits for (or any other) is queued on this core,
  // that one runs rather than the spin; on an idle core a yield costs a
  // system call.
  template <class Pred>
  static bool spin_until(Pred pred);

  void wait_until_done(std::size_t chunks);

  // Worker `index` (1, 2, ...): takes part in every job of more than `index`
  // threads, from the first job after generation `seen`.
  void worker(unsigned index, std::uint32_t seen);

  std::mutex dispatch_;           // held by the caller for the whole of a job
  std::uint32_t generation_ = 0;  // of the last job (under dispatch_)
  std::atomic<unsigned> started_{0};

  Job job_;
  Share shares_[max_threads];
  Done done_;
  std::mutex error_mutex_;
  std::exception_ptr error_;

  std::mutex sleep_mutex_;
  std::condition_variable wake_;      // workers: a new job
  std::condition_variable finished_;  // the caller: the last chunk is done
  std::atomic<unsigned> sleepers_{0};
};

}  // namespace partc::detail
