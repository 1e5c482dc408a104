#include "smap/apps/InterruptWatcher.h"

#include <pthread.h>

#include <ctime>

namespace smap::apps
{
InterruptWatcher::InterruptWatcher()
{
    sigemptyset(&watched_);
    sigaddset(&watched_, SIGINT);
    sigaddset(&watched_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &watched_, &previousMask_);
    thread_ = std::thread([this] { run(); });
}

InterruptWatcher::~InterruptWatcher()
{
    stop_ = true;
    if (thread_.joinable())
        thread_.join();
    pthread_sigmask(SIG_SETMASK, &previousMask_, nullptr);
}

void InterruptWatcher::run()
{
    const timespec period{0, 100 * 1000 * 1000};
    while (!stop_)
    {
        const int s = sigtimedwait(&watched_, nullptr, &period);
        if (s <= 0)
            continue;
        if (signal_.load() != 0)
        {
            // Second signal: the default action (terminate) right away.
            std::signal(s, SIG_DFL);
            pthread_sigmask(SIG_UNBLOCK, &watched_, nullptr);
            raise(s);
        }
        signal_ = s;
    }
}
}  // namespace smap::apps
