// Ctrl-C (SIGINT) and SIGTERM turned into a flag that a long run polls, so that it stops
// reading input and still writes complete outputs for what it processed. Create it before any
// other thread: it blocks the signals in the creating thread (and so in every thread created
// afterwards) and waits for them in its own thread. A second signal ends the process at once,
// as the default handler does. The signal mask is restored on destruction.
#pragma once

#include <atomic>
#include <csignal>
#include <thread>

namespace smap::apps
{
class InterruptWatcher
{
public:
    InterruptWatcher();
    ~InterruptWatcher();
    InterruptWatcher(const InterruptWatcher&) = delete;
    InterruptWatcher& operator=(const InterruptWatcher&) = delete;

    bool interrupted() const { return signal_.load() != 0; }
    /// The signal received (SIGINT, SIGTERM), 0 when none.
    int signal() const { return signal_.load(); }

private:
    void run();

    sigset_t watched_{};
    sigset_t previousMask_{};
    std::atomic<int> signal_{0};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};
}  // namespace smap::apps
