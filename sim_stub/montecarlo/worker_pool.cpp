#include "sim_stub/montecarlo/worker_pool.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rse::sim::mc {

namespace {

struct Worker {
    pid_t pid = -1;
    int toChild = -1;    // parent writes seeds
    int fromChild = -1;  // parent reads lines
    bool busy = false;
    std::uint64_t seed = 0;
    std::string inbox;   // what the child wrote, not yet a whole answer
};

bool writeAll(int fd, const std::string& text) {
    std::size_t off = 0;
    while (off < text.size()) {
        const ssize_t n = ::write(fd, text.data() + off, text.size() - off);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return false;
        }
        off += static_cast<std::size_t>(n);
    }
    return true;
}

// The child: a seed per line in, its row and timing lines out, until EOF.
[[noreturn]] void childLoop(int in, int out, const std::function<SeedRun(std::uint64_t)>& work) {
    std::string pending;
    char buf[256];
    for (;;) {
        const std::size_t nl = pending.find('\n');
        if (nl != std::string::npos) {
            const std::string line = pending.substr(0, nl);
            pending.erase(0, nl + 1);
            const std::uint64_t seed = std::strtoull(line.c_str(), nullptr, 10);
            const SeedRun r = work(seed);
            if (!writeAll(out, r.row + "\n" + r.timing + "\n")) {
                _exit(3);
            }
            continue;
        }
        const ssize_t n = ::read(in, buf, sizeof buf);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            _exit(0);
        }
        pending.append(buf, static_cast<std::size_t>(n));
    }
}

bool startWorker(Worker* w, std::vector<Worker>& all, const std::function<SeedRun(std::uint64_t)>& work,
                 std::string* error) {
    int down[2], up[2];
    if (pipe(down) != 0) {
        *error = std::string("pipe: ") + std::strerror(errno);
        return false;
    }
    if (pipe(up) != 0) {
        *error = std::string("pipe: ") + std::strerror(errno);
        close(down[0]);
        close(down[1]);
        return false;
    }
    std::fflush(nullptr);  // nothing buffered is written twice
    const pid_t pid = fork();
    if (pid < 0) {
        *error = std::string("fork: ") + std::strerror(errno);
        for (int fd : {down[0], down[1], up[0], up[1]}) {
            close(fd);
        }
        return false;
    }
    if (pid == 0) {
        // The other workers' pipes are theirs: keep none open here, or their
        // EOF would never come.
        for (const Worker& o : all) {
            if (o.toChild >= 0) {
                close(o.toChild);
            }
            if (o.fromChild >= 0) {
                close(o.fromChild);
            }
        }
        close(down[1]);
        close(up[0]);
        childLoop(down[0], up[1], work);
    }
    close(down[0]);
    close(up[1]);
    fcntl(down[1], F_SETFD, FD_CLOEXEC);
    fcntl(up[0], F_SETFD, FD_CLOEXEC);
    w->pid = pid;
    w->toChild = down[1];
    w->fromChild = up[0];
    w->busy = false;
    w->inbox.clear();
    return true;
}

std::string endOf(pid_t pid) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status)) {
        return "signal_" + std::to_string(WTERMSIG(status));
    }
    return "exit_" + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

void closeWorker(Worker* w) {
    if (w->toChild >= 0) {
        close(w->toChild);
    }
    if (w->fromChild >= 0) {
        close(w->fromChild);
    }
    w->toChild = w->fromChild = -1;
}

// The parent's side of one run: the workers, the seeds handed out and those
// finished. run() starts the workers, gives each a seed, then reads their
// answers (and their ends) as they come until every seed is finished.
class Pool {
public:
    Pool(const std::vector<std::uint64_t>& seeds, int jobs, const std::function<SeedRun(std::uint64_t)>& work,
         const std::function<void(std::uint64_t, const SeedRun&)>& done, std::string* error)
        : seeds_(seeds),
          work_(work),
          done_(done),
          error_(error),
          workers_(std::min<std::size_t>(static_cast<std::size_t>(jobs < 1 ? 1 : jobs), seeds.size())) {}

    bool run() {
        bool ok = startAll();
        while (ok && finished_ < seeds_.size()) {
            ok = readAnswers();
        }
        stopAll(ok);
        return ok;
    }

private:
    bool startAll() {
        for (Worker& w : workers_) {
            if (!startWorker(&w, workers_, work_, error_)) {
                return false;
            }
        }
        for (Worker& w : workers_) {
            give(w);
        }
        return true;
    }

    // The next seed to w, or (none left) its pipe closed: EOF tells it to stop.
    void give(Worker& w) {
        if (next_ < seeds_.size()) {
            const std::uint64_t seed = seeds_[next_++];
            if (writeAll(w.toChild, std::to_string(seed) + "\n")) {
                w.busy = true;
                w.seed = seed;
                return;
            }
            // The worker is gone: its end is read later; give the seed back.
            --next_;
            return;
        }
        closeWorker(&w);
    }

    // One poll of the workers' pipes, and what the readable ones wrote.
    bool readAnswers() {
        std::vector<pollfd> fds;
        std::vector<Worker*> owners;
        for (Worker& w : workers_) {
            if (w.fromChild >= 0) {
                fds.push_back(pollfd{w.fromChild, POLLIN, 0});
                owners.push_back(&w);
            }
        }
        if (fds.empty()) {
            *error_ = "no worker left with seeds still to run";
            return false;
        }
        if (poll(fds.data(), fds.size(), -1) < 0) {
            if (errno == EINTR) {
                return true;
            }
            *error_ = std::string("poll: ") + std::strerror(errno);
            return false;
        }
        for (std::size_t i = 0; i < fds.size(); ++i) {
            if (fds[i].revents != 0 && !readFrom(*owners[i])) {
                return false;
            }
        }
        return true;
    }

    // What w wrote: part of an answer, an answer (the seed done, the next
    // given), or its end.
    bool readFrom(Worker& w) {
        char buf[4096];
        const ssize_t n = ::read(w.fromChild, buf, sizeof buf);
        if (n < 0 && errno == EINTR) {
            return true;
        }
        if (n <= 0) {
            return onEnd(w);
        }
        w.inbox.append(buf, static_cast<std::size_t>(n));
        // An answer is two lines: the row, then the timing.
        std::size_t first = w.inbox.find('\n');
        std::size_t second = first == std::string::npos ? first : w.inbox.find('\n', first + 1);
        if (w.busy && second != std::string::npos) {
            SeedRun r{w.inbox.substr(0, first), w.inbox.substr(first + 1, second - first - 1)};
            w.inbox.erase(0, second + 1);
            w.busy = false;
            ++finished_;
            done_(w.seed, r);
            give(w);
        }
        return true;
    }

    // EOF: the worker ended; mid-seed, that seed crashed. Another takes its
    // place while seeds are left.
    bool onEnd(Worker& w) {
        const bool wasBusy = w.busy;
        const std::uint64_t seed = w.seed;
        closeWorker(&w);
        const std::string why = endOf(w.pid);
        w.pid = -1;
        w.busy = false;
        if (wasBusy) {
            ++finished_;
            done_(seed, SeedRun{crashedRow(seed, why), ""});
        }
        if (next_ < seeds_.size()) {
            if (!startWorker(&w, workers_, work_, error_)) {
                return false;
            }
            give(w);
        }
        return true;
    }

    // Every worker's pipes closed and its end awaited (after a failure, each
    // told to stop first).
    void stopAll(bool ok) {
        for (Worker& w : workers_) {
            closeWorker(&w);
            if (w.pid > 0) {
                if (!ok) {
                    kill(w.pid, SIGTERM);
                }
                (void)endOf(w.pid);
                w.pid = -1;
            }
        }
    }

    const std::vector<std::uint64_t>& seeds_;
    const std::function<SeedRun(std::uint64_t)>& work_;
    const std::function<void(std::uint64_t, const SeedRun&)>& done_;
    std::string* error_;
    std::vector<Worker> workers_;
    std::size_t next_ = 0;      // seeds_[next_] is the next to give
    std::size_t finished_ = 0;  // answered or crashed
};

}  // namespace

bool runOnWorkers(const std::vector<std::uint64_t>& seeds, int jobs,
                  const std::function<SeedRun(std::uint64_t)>& work,
                  const std::function<void(std::uint64_t, const SeedRun&)>& done, std::string* error) {
    // A worker that died leaves a broken pipe: a write to it must fail, not kill us.
    struct sigaction ignore {};
    struct sigaction previous {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &previous);
    Pool pool(seeds, jobs, work, done, error);
    const bool ok = pool.run();
    sigaction(SIGPIPE, &previous, nullptr);
    return ok;
}

}  // namespace rse::sim::mc
