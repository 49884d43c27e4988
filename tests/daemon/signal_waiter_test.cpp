// Signals as events: a pending SIGHUP or SIGTERM is returned by wait(), nothing is a
// timeout, and the mask is restored afterwards.
#include "daemon/signal_waiter.hpp"

#include <pthread.h>
#include <signal.h>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(SignalWaiter, BlockedSignalsBecomeEvents) {
  SignalWaiter waiter;
  EXPECT_EQ(waiter.wait(1'000'000), SignalWaiter::Event::none);
  raise(SIGHUP);  // blocked: stays pending instead of ending the test
  EXPECT_EQ(waiter.wait(1'000'000'000), SignalWaiter::Event::hangup);
  EXPECT_EQ(waiter.last_signal(), SIGHUP);
  raise(SIGTERM);
  EXPECT_EQ(waiter.wait(1'000'000'000), SignalWaiter::Event::terminate);
  EXPECT_EQ(waiter.last_signal(), SIGTERM);
  raise(SIGINT);
  EXPECT_EQ(waiter.wait(1'000'000'000), SignalWaiter::Event::terminate);
  EXPECT_EQ(waiter.last_signal(), SIGINT);
}

TEST(SignalWaiter, RestoresTheMask) {
  sigset_t before;
  pthread_sigmask(SIG_BLOCK, nullptr, &before);
  ASSERT_FALSE(sigismember(&before, SIGTERM));
  {
    SignalWaiter waiter;
    sigset_t during;
    pthread_sigmask(SIG_BLOCK, nullptr, &during);
    EXPECT_TRUE(sigismember(&during, SIGTERM));
    EXPECT_TRUE(sigismember(&during, SIGHUP));
  }
  sigset_t after;
  pthread_sigmask(SIG_BLOCK, nullptr, &after);
  EXPECT_FALSE(sigismember(&after, SIGTERM));
}

}  // namespace
}  // namespace ccdlane
