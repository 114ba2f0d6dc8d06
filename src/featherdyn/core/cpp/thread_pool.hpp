// The core's own thread pool (std::thread, no OpenMP) for the batched calls.
//
// * parallel_for(n, fn) runs fn(begin, end) over chunks of [0, n); the calling thread works too.
// * Several threads may call parallel_for at once: each call is a job in a shared queue.
// * A worker that finishes a job polls for the next one for a short while (kSpinMicroseconds) before it sleeps,
//   and the caller polls for the workers' last chunks before it sleeps: waking a sleeping thread costs tens of µs
//   in a VM (a halted virtual CPU must be scheduled again), as much as a whole short batch, and batched calls
//   usually come back to back (a training loop, a sweep).
// * fork: the child has none of the parent's threads, so the child drops the pool (leaking it;
//   its threads are gone) and builds a new one on first use (pthread_atfork, plus a pid check).
#pragma once

#if defined(_WIN32)
#include <process.h>  // _getpid (Windows has no fork: no atfork handler either)
#else
#include <pthread.h>
#include <sched.h>
#include <unistd.h>
#endif
#if defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#include <immintrin.h>  // _mm_pause
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

namespace fdcore {

class ThreadPool {
 public:
  explicit ThreadPool(int nthreads) : nthreads_(std::max(1, nthreads)) {
    for (int t = 1; t < nthreads_; ++t) workers_.emplace_back([this] { work(); });
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      stopping_.store(true, std::memory_order_release);
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
  }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return nthreads_; }

  void parallel_for(std::int64_t n, const std::function<void(std::int64_t, std::int64_t)>& fn) {
    if (n <= 0) return;
    // about eight chunks per thread: a thread that wakes late, or rows of uneven cost, leave at most a small
    // chunk to wait for (a batch of 200 talos contact states is 25 SIMD groups of ~20 µs: chunks of 3 groups
    // left the caller waiting for the worker's last one); a chunk costs one atomic increment
    const std::int64_t chunk = std::max<std::int64_t>(1, n / (8 * nthreads_));
    if (nthreads_ == 1 || n <= chunk) {
      fn(0, n);
      return;
    }
    Job job{fn, n, chunk};
    bool sleeping;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(&job);
      pending_.store(static_cast<int>(queue_.size()), std::memory_order_release);
      sleeping = sleepers_ > 0;  // a worker between its poll and its wait takes the lock and sees the job
    }
    if (sleeping) wake_.notify_all();
    run_chunks(job);
    // the workers' last chunks: polled for a while too (a sleeping caller is as slow to wake as a worker)
    auto done = [&] {
      return job.finished.load(std::memory_order_acquire) == job.nchunks() && job.users.load() == 0;
    };
    spin_until(done);
    std::unique_lock<std::mutex> lock(mutex_);
    remove(&job);
    done_.wait(lock, done);  // (users changes under the lock: a worker that took the job meanwhile is waited for)
  }

 private:
  struct Job {
    const std::function<void(std::int64_t, std::int64_t)>& fn;
    std::int64_t n, chunk;
    std::atomic<std::int64_t> next{0};
    std::atomic<std::int64_t> finished{0};
    std::atomic<int> users{0};  // workers inside run_chunks (changed with mutex_ held; read by the polling caller)
    Job(const std::function<void(std::int64_t, std::int64_t)>& f, std::int64_t n_, std::int64_t c)
        : fn(f), n(n_), chunk(c) {}
    std::int64_t nchunks() const { return (n + chunk - 1) / chunk; }
  };

  void run_chunks(Job& job) {
    for (;;) {
      const std::int64_t c = job.next.fetch_add(1);
      if (c >= job.nchunks()) return;
      const std::int64_t begin = c * job.chunk;
      job.fn(begin, std::min(job.n, begin + job.chunk));
      job.finished.fetch_add(1);
    }
  }

  void remove(Job* job) {  // with mutex_ held
    auto it = std::find(queue_.begin(), queue_.end(), job);
    if (it != queue_.end()) queue_.erase(it);
    pending_.store(static_cast<int>(queue_.size()), std::memory_order_release);
  }

  static constexpr int kSpinMicroseconds = 100;

  // Poll `ready` (without the lock) until it holds or kSpinMicroseconds have passed. Between short runs of pauses
  // the thread yields its core, so that on a machine with more runnable threads than cores it does not take time
  // from a thread with work to do.
  template <class Ready>
  static void spin_until(const Ready& ready) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(kSpinMicroseconds);
    for (;;) {
      for (int k = 0; k < 32; ++k) {
        if (ready()) return;
#if defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
        _mm_pause();
#elif defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
      if (std::chrono::steady_clock::now() >= until) return;
      std::this_thread::yield();
    }
  }

  void work() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (!stop_ && queue_.empty()) {
        lock.unlock();
        spin_until([&] {
          return pending_.load(std::memory_order_acquire) > 0 || stopping_.load(std::memory_order_acquire);
        });
        lock.lock();
      }
      ++sleepers_;
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      --sleepers_;
      if (stop_) return;
      Job* job = queue_.front();
      ++job->users;
      lock.unlock();
      run_chunks(*job);
      lock.lock();
      remove(job);  // exhausted: no more chunks to hand out
      --job->users;
      done_.notify_all();
    }
  }

  int nthreads_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<Job*> queue_;
  bool stop_ = false;
  int sleepers_ = 0;                // workers waiting on wake_ (guarded by mutex_)
  std::atomic<int> pending_{0};     // queue_.size(), readable without the lock (a polling worker's test)
  std::atomic<bool> stopping_{false};
};

// The cores this process may run on (its CPU affinity on Linux).
inline int available_cores() {
#if defined(__linux__)
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
#endif
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// This process's id (a forked child's differs from its parent's).
#if defined(_WIN32)
using process_id = int;
inline process_id current_process() { return _getpid(); }
#else
using process_id = pid_t;
inline process_id current_process() { return getpid(); }
#endif

// The process-wide pool, rebuilt after fork and by set_num_threads.
class GlobalPool {
 public:
  static GlobalPool& instance() {
    static GlobalPool* g = new GlobalPool();  // never destroyed: worker threads must not outlive it at exit
    return *g;
  }

  std::shared_ptr<ThreadPool> get() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pool_ || pid_ != current_process()) {
      if (pid_ != current_process()) forget();
      pool_ = std::make_shared<ThreadPool>(nthreads_);
      pid_ = current_process();
    }
    return pool_;
  }

  void set_num_threads(int n) {
    std::shared_ptr<ThreadPool> old;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      nthreads_ = n > 0 ? n : available_cores();
      if (pid_ == current_process()) old.swap(pool_);  // running batches keep their pool until they finish
      else forget();
    }
  }

  int num_threads() {
    std::lock_guard<std::mutex> lock(mutex_);
    return nthreads_;
  }

 private:
  GlobalPool() : nthreads_(available_cores()), pid_(current_process()) {
#if !defined(_WIN32)
    pthread_atfork([] { instance().mutex_.lock(); }, [] { instance().mutex_.unlock(); },
                   [] {
                     GlobalPool& g = instance();
                     g.mutex_.unlock();
                     g.forget();
                   });
#endif
  }
  // In a forked child the pool's threads do not exist: drop it without running its destructor.
  void forget() {
    new (&pool_) std::shared_ptr<ThreadPool>();
    pid_ = current_process();
  }

  std::mutex mutex_;
  std::shared_ptr<ThreadPool> pool_;
  int nthreads_;
  process_id pid_;
};

}  // namespace fdcore
