// WorkSharing: an offer is done exactly once, by its owner when nobody took
// it, else by the thread that took it; a waiting owner does other offers; a
// task's exception reaches its owner.
#include "core/work_sharing.h"

#include <gtest/gtest.h>

#include <future>
#include <new>
#include <stdexcept>
#include <thread>

namespace mbao {
namespace {

// A task runs a function on the thread that does it; the context counts the
// tasks that thread did.
struct Task {
  std::function<int(int& done_here)> run;
};
using Sharing = WorkSharing<Task, int, int>;

Sharing::Do run_task() {
  return [](Task& task, int& done_here) {
    ++done_here;
    return task.run(done_here);
  };
}

TEST(WorkSharing, TheOwnerTakesBackWhatNobodyTook) {
  Sharing sharing(
      0, [] { return 0; }, run_task());
  bool ran = false;
  const Sharing::OfferHandle offer = sharing.offer({[&ran](int&) {
    ran = true;
    return 7;
  }});
  std::optional<Task> task = sharing.take_back(offer);
  ASSERT_TRUE(task.has_value());
  EXPECT_FALSE(ran);
  int done_here = 0;
  EXPECT_EQ(task->run(done_here), 7);
  EXPECT_TRUE(ran);
}

TEST(WorkSharing, AnIdleThreadTakesAnOfferItsOwnerHasNotComeBackTo) {
  Sharing sharing(
      1, [] { return 0; }, run_task());
  std::promise<std::thread::id> started;
  const Sharing::OfferHandle offer = sharing.offer({[&started](int&) {
    started.set_value(std::this_thread::get_id());
    return 7;
  }});
  const std::thread::id taker = started.get_future().get();  // the helper is idle: it takes the offer
  EXPECT_NE(taker, std::this_thread::get_id());
  EXPECT_FALSE(sharing.take_back(offer).has_value());
  int context = 0;
  EXPECT_EQ(sharing.wait_for(offer, context), 7);
  EXPECT_EQ(context, 0);
}

TEST(WorkSharing, AWaitingOwnerDoesTheOffersOfTheTaskItWaitsFor) {
  // The helper takes the outer task, which offers an inner one and waits
  // until someone takes it: only the owner, waiting for the outer task, can.
  Sharing sharing(
      1, [] { return 0; }, run_task());
  const std::thread::id owner = std::this_thread::get_id();
  std::thread::id inner_ran_on;
  std::promise<void> outer_started;
  const Sharing::OfferHandle outer = sharing.offer({[&](int& helper_context) {
    outer_started.set_value();
    std::promise<void> inner_started;
    const Sharing::OfferHandle inner = sharing.offer({[&](int&) {
      inner_ran_on = std::this_thread::get_id();
      inner_started.set_value();
      return 5;
    }});
    inner_started.get_future().wait();
    EXPECT_FALSE(sharing.take_back(inner).has_value());
    return 10 + sharing.wait_for(inner, helper_context);
  }});
  outer_started.get_future().wait();
  EXPECT_FALSE(sharing.take_back(outer).has_value());
  int owner_context = 0;
  EXPECT_EQ(sharing.wait_for(outer, owner_context), 15);
  EXPECT_EQ(inner_ran_on, owner);
  EXPECT_EQ(owner_context, 1);
}

TEST(WorkSharing, ATaskThrowsToItsOwner) {
  Sharing sharing(
      1, [] { return 0; }, run_task());
  std::promise<void> started;
  const Sharing::OfferHandle offer = sharing.offer({[&started](int&) -> int {
    started.set_value();
    throw std::runtime_error("broken task");
  }});
  started.get_future().wait();
  int context = 0;
  EXPECT_THROW(
      {
        try {
          sharing.wait_for(offer, context);
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "broken task");
          throw;
        }
      },
      std::runtime_error);
}

// Sums first..last-1 by halving, offering the upper half as the kd-tree
// builder offers a node's above child.
int sum_range(Sharing& sharing, int first, int last, int& context) {
  if (last - first <= 8) {
    int sum = 0;
    for (int i = first; i < last; ++i) sum += i;
    return sum;
  }
  const int middle = first + (last - first) / 2;
  const Sharing::OfferHandle upper = sharing.offer(
      {[&sharing, middle, last](int& taker_context) { return sum_range(sharing, middle, last, taker_context); }});
  const int lower = sum_range(sharing, first, middle, context);
  std::optional<Task> taken_back = sharing.take_back(upper);
  return lower + (taken_back ? taken_back->run(context) : sharing.wait_for(upper, context));
}

TEST(WorkSharing, EveryOfferIsDoneOnceWhateverTheThreads) {
  for (int helpers : {0, 1, 3, 7}) {
    Sharing sharing(
        helpers, [] { return 0; }, run_task());
    int context = 0;
    const int n = 20000;
    EXPECT_EQ(sum_range(sharing, 0, n, context), n * (n - 1) / 2) << helpers << " helpers";
  }
}

TEST(WorkSharing, HelpersWithoutAContextLeaveTheOffersToTheirOwners) {
  Sharing sharing(
      3, []() -> int { throw std::bad_alloc(); }, run_task());
  int context = 0;
  EXPECT_EQ(sum_range(sharing, 0, 20000, context), 20000 * 19999 / 2);
}

}  // namespace
}  // namespace mbao
