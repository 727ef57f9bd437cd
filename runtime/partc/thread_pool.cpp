// partc/thread_pool.cpp: ThreadPool's dispatch and workers (thread_pool.hpp
// says how they behave), compiled once: the one pool of the process lives here.
#include "partc/thread_pool.hpp"

#include <algorithm>
#include <system_error>
#include <thread>

#if defined(__unix__) || defined(__APPLE__)
#include <pthread.h>
#endif

namespace partc::detail {

template <class Pred>
bool ThreadPool::spin_until(Pred pred) {
  const auto deadline = std::chrono::steady_clock::now() + spin_wait;
  for (;;) {
    for (int k = 0; k < 64; ++k) {
      if (pred()) return true;
      cpu_relax();
    }
    if (std::chrono::steady_clock::now() >= deadline) return pred();
    std::this_thread::yield();
  }
}

void ThreadPool::wait_until_done(std::size_t chunks) {
  const auto done = [&] { return done_.chunks.load(std::memory_order_acquire) == chunks; };
  if (spin_until(done)) return;
  done_.caller_sleeps.store(true, std::memory_order_seq_cst);
  if (!done()) {
    std::unique_lock<std::mutex> sleep(sleep_mutex_);
    finished_.wait(sleep, done);
  }
  done_.caller_sleeps.store(false, std::memory_order_relaxed);
}

void ThreadPool::worker(unsigned index, std::uint32_t seen) {
  inside_job() = true;  // a nested parallel_for runs serially
  const auto fresh = [&] { return generation(job_.word.load(std::memory_order_seq_cst)) != seen; };
  for (;;) {
    if (!spin_until(fresh)) {
      sleepers_.fetch_add(1, std::memory_order_seq_cst);
      {
        std::unique_lock<std::mutex> sleep(sleep_mutex_);
        wake_.wait(sleep, fresh);
      }
      sleepers_.fetch_sub(1, std::memory_order_relaxed);
    }
    const std::uint64_t word = job_.word.load(std::memory_order_acquire);
    seen = generation(word);
    const auto threads = static_cast<unsigned>(word & 0xffffffffu);
    if (index < threads) work(index, seen, threads);
  }
}

ThreadPool*& ThreadPool::current() {
  static ThreadPool* pool = [] {
#if defined(__unix__) || defined(__APPLE__)
    pthread_atfork(nullptr, nullptr, [] { current() = new ThreadPool; });
#endif
    return new ThreadPool;
  }();
  return pool;
}

bool& ThreadPool::inside_job() {
  thread_local bool inside = false;
  return inside;
}

bool ThreadPool::run_erased(unsigned threads, std::size_t chunks, Task task, void* context) {
  if (inside_job() || chunks == 0 || chunks > max_chunks) return false;
  std::unique_lock<std::mutex> lock(dispatch_, std::try_to_lock);
  if (!lock.owns_lock()) return false;
  inside_job() = true;
  struct Leave {
    ~Leave() { inside_job() = false; }
  } leave;
  threads =
      start_workers(std::min<std::size_t>({std::max(threads, 1u), max_threads, chunks}) - 1) + 1;

  const std::uint32_t job = ++generation_;
  job_.task = task;
  job_.context = context;
  job_.chunks = chunks;
  job_.failed.store(false, std::memory_order_relaxed);
  error_ = nullptr;
  done_.chunks.store(0, std::memory_order_relaxed);
  const std::size_t size = chunks / threads, longer = chunks % threads;
  for (unsigned k = 0, first = 0; k < threads; ++k) {
    const unsigned stop = first + static_cast<unsigned>(size + (k < longer ? 1 : 0));
    shares_[k].word.store(share_word(job, first, stop), std::memory_order_relaxed);
    first = stop;
  }
  job_.word.store(std::uint64_t{job} << 32 | threads, std::memory_order_seq_cst);
  if (sleepers_.load(std::memory_order_seq_cst) > 0) {
    { std::lock_guard<std::mutex> sleep(sleep_mutex_); }
    wake_.notify_all();
  }
  work(0, job, threads);
  wait_until_done(chunks);
  if (error_) std::rethrow_exception(error_);
  return true;
}

unsigned ThreadPool::start_workers(std::size_t count) {
  unsigned have = started_.load(std::memory_order_relaxed);
  for (; have < count; ++have) {
    try {
      std::thread(&ThreadPool::worker, this, have + 1, generation_).detach();
    } catch (const std::system_error&) {
      break;
    }
    started_.store(have + 1, std::memory_order_relaxed);
  }
  return static_cast<unsigned>(std::min<std::size_t>(have, count));
}

std::ptrdiff_t ThreadPool::claim(unsigned k, std::uint32_t job, bool own) {
  std::atomic<std::uint64_t>& word = shares_[k].word;
  std::uint64_t w = word.load(std::memory_order_relaxed);
  for (;;) {
    const std::size_t f = front(w), b = back(w);
    if (generation(w) != job || f >= b) return -1;
    const std::uint64_t claimed = own ? share_word(job, f + 1, b) : share_word(job, f, b - 1);
    if (word.compare_exchange_weak(w, claimed, std::memory_order_acquire,
                                   std::memory_order_relaxed))
      return static_cast<std::ptrdiff_t>(own ? f : b - 1);
  }
}

void ThreadPool::work(unsigned self, std::uint32_t job, unsigned threads) {
  std::size_t finished = 0, chunks = 0;
  for (unsigned step = 0; step < threads; ++step) {
    const unsigned k = (self + step) % threads;
    for (std::ptrdiff_t c; (c = claim(k, job, step == 0)) >= 0; ++finished) {
      chunks = job_.chunks;
      if (job_.failed.load(std::memory_order_relaxed)) continue;
      try {
        job_.task(job_.context, static_cast<std::size_t>(c));
      } catch (...) {
        std::lock_guard<std::mutex> guard(error_mutex_);
        if (!error_) error_ = std::current_exception();
        job_.failed.store(true, std::memory_order_relaxed);
      }
    }
  }
  if (finished == 0) return;
  // After this the job may end, and its fields change: touch none of them.
  if (done_.chunks.fetch_add(finished, std::memory_order_seq_cst) + finished == chunks &&
      done_.caller_sleeps.load(std::memory_order_seq_cst)) {
    { std::lock_guard<std::mutex> sleep(sleep_mutex_); }
    finished_.notify_one();
  }
}

}  // namespace partc::detail
