// Work shared between a fixed number of threads, for recursive builds whose
// parts are uneven in size and unknown in advance.
//
// A thread that splits its work in two offers one half and goes on with the
// other. When it comes back to the half it offered, it takes it back and does
// it itself, unless an idle thread took it meanwhile; then it waits for it, and
// while it waits it takes other offers, so no thread idles while any offer is
// open. Idle threads take the oldest offer first: in a recursive build it lies
// nearest the root, so it is the largest.
//
// Deciding who does a half when it is due, not when it is split off, is what
// keeps threads busy to the end: with a decision at the split, a thread that
// finishes early finds every half already assigned.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace mbao {

// Task: what an offer holds. Context: what a thread reuses from task to task
// (each thread makes its own). Result: what doing a task gives.
template <class Task, class Context, class Result>
class WorkSharing {
 public:
  using Do = std::function<Result(Task&, Context&)>;

  class Offer {
    friend class WorkSharing;
    explicit Offer(Task&& task) : task_(std::move(task)) {}
    Task task_;
    bool taken_ = false, finished_ = false;  // guarded by the pool's mutex
    std::optional<Result> result_;
    std::exception_ptr error_;
  };
  using OfferHandle = std::shared_ptr<Offer>;

  // Starts `helpers` threads, each with a context from make_context, that
  // take offers until the pool is destroyed.
  // A helper whose context cannot be made does nothing: the offers it would
  // have taken are done by the threads that made them.
  WorkSharing(int helpers, std::function<Context()> make_context, Do do_task) : do_task_(std::move(do_task)) {
    try {
      for (int i = 0; i < helpers; ++i)
        helpers_.emplace_back([this, make_context] {
          std::optional<Context> context;
          try {
            context.emplace(make_context());
          } catch (...) {
            return;
          }
          help_until_stopped(*context);
        });
    } catch (...) {  // a thread that could not start: the started ones must not outlive this
      stop_helpers();
      throw;
    }
  }

  // Helpers finish the task they are doing, take no other, and are joined.
  ~WorkSharing() { stop_helpers(); }

  WorkSharing(const WorkSharing&) = delete;
  WorkSharing& operator=(const WorkSharing&) = delete;

  OfferHandle offer(Task task) {
    OfferHandle offer(new Offer(std::move(task)));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open_.push_back(offer);
    }
    changed_.notify_one();
    return offer;
  }

  // The offer's task, if no other thread took it; the caller then does it.
  std::optional<Task> take_back(const OfferHandle& offer) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (offer->taken_) return std::nullopt;
    offer->taken_ = true;
    for (auto it = open_.rbegin(); it != open_.rend(); ++it)
      if (*it == offer) {
        open_.erase(std::next(it).base());
        break;
      }
    return std::move(offer->task_);
  }

  // The result of an offer another thread took, doing other offers with
  // `context` until it is there. Rethrows what the task threw.
  Result wait_for(const OfferHandle& offer, Context& context) {
    std::unique_lock<std::mutex> lock(mutex_);
    help_until(lock, context, [&offer] { return offer->finished_; });
    if (offer->error_) std::rethrow_exception(offer->error_);
    return std::move(*offer->result_);
  }

 private:
  void stop_helpers() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    for (std::thread& helper : helpers_) helper.join();
  }

  void help_until_stopped(Context& context) {
    std::unique_lock<std::mutex> lock(mutex_);
    help_until(lock, context, [this] { return stopping_; });
  }

  // Does open offers, or sleeps while there are none, until `done` (read
  // under the lock).
  template <class Done>
  void help_until(std::unique_lock<std::mutex>& lock, Context& context, const Done& done) {
    while (!done()) {
      if (open_.empty()) {
        changed_.wait(lock);
      } else {
        do_oldest(lock, context);
      }
    }
  }

  // Takes the oldest open offer and does it, with `lock` released meanwhile.
  void do_oldest(std::unique_lock<std::mutex>& lock, Context& context) {
    OfferHandle offer = std::move(open_.front());
    open_.pop_front();
    offer->taken_ = true;
    lock.unlock();
    try {
      offer->result_.emplace(do_task_(offer->task_, context));
    } catch (...) {
      offer->error_ = std::current_exception();
    }
    lock.lock();
    offer->finished_ = true;
    changed_.notify_all();
  }

  Do do_task_;
  std::mutex mutex_;
  std::condition_variable changed_;  // an offer made or finished, or stopping
  std::deque<OfferHandle> open_;
  bool stopping_ = false;
  std::vector<std::thread> helpers_;  // last: started after everything they use
};

}  // namespace mbao
