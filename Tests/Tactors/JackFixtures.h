#pragma once
// A private JACK server with the dummy backend (never the default server: its name is unique and
// reaches our clients and child processes through JACK_DEFAULT_SERVER), and a small recording
// client with N input ports. Used by the live tactor tests; no sleep decides a result.
#include "Common/Eventually.h"
#include <jack/jack.h>
#include <atomic>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <cstdlib>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace armadillo::test {

class JackServer {
public:
    /// Starts `jackd -n NAME -d dummy -r RATE -p PERIOD -P PLAYBACK -C 0` (real-time scheduling
    /// where the system grants it, as a rig runs; jackd goes on without it otherwise) and waits
    /// until a client can open (false from running() when it never does).
    JackServer(int rate = 48000, int period = 256, int playback = 2)
    {
        // libjack reports every refused connection on stderr while the server starts: not the test's business.
        jack_set_error_function([](const char*) {});
        jack_set_info_function([](const char*) {});
        name_ = "armadillo_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++);
        ::setenv("JACK_DEFAULT_SERVER", name_.c_str(), 1);
        const std::string r = std::to_string(rate), p = std::to_string(period), P = std::to_string(playback);
        pid_ = ::fork();
        if (pid_ == 0) {
            // Quiet child: jackd's banner is not the test's business. Only async-signal-safe
            // calls until the exec (the test process has threads: a client's, a server watcher's).
            const int quiet = ::open("/dev/null", O_WRONLY);
            ::dup2(quiet, STDOUT_FILENO);
            ::dup2(quiet, STDERR_FILENO);
            ::execlp("jackd", "jackd", "-n", name_.c_str(), "-d", "dummy", "-r", r.c_str(), "-p", p.c_str(), "-P", P.c_str(), "-C", "0",
                     static_cast<char*>(nullptr));
            ::_exit(127);
        }
        running_ = pid_ > 0 && armadillo::testing::eventually([&] {
                       int status = 0;
                       if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                           pid_ = -1;
                           return true;   // died: stop waiting
                       }
                       jack_status_t st {};
                       jack_client_t* c = jack_client_open("probe", JackNoStartServer, &st);
                       if (!c) return false;
                       jack_client_close(c);
                       return true;
                   }, 20.0) && pid_ > 0;
    }
    ~JackServer()
    {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            int status = 0;
            const bool ended = armadillo::testing::eventually([&] { return ::waitpid(pid_, &status, WNOHANG) == pid_; }, 10.0);
            if (!ended) {
                ::kill(pid_, SIGKILL);
                ::waitpid(pid_, &status, 0);
            }
        }
        ::unsetenv("JACK_DEFAULT_SERVER");
    }
    JackServer(const JackServer&) = delete;
    JackServer& operator=(const JackServer&) = delete;
    bool running() const noexcept { return running_; }
    const std::string& name() const noexcept { return name_; }

private:
    static int& counter()
    {
        static int n = 0;
        return n;
    }
    std::string name_;
    pid_t pid_ = -1;
    bool running_ = false;
};

/// A JACK client "rec" with input ports in_1…in_N that records every period into preallocated
/// buffers (up to `seconds`), from its activation on, and the steady-clock time at which each
/// period reached it (right after the clients upstream of it, the tactor output among them, ran
/// that period): a server that falls behind on a loaded machine does not make up for lost time,
/// so the frame count alone is not a clock. (JACK's own cycle times, jack_get_cycle_times, are the
/// driver's filtered estimates: with the dummy backend they even run backwards after a stall.)
class JackRecorder {
public:
    JackRecorder(int channels, double seconds)
    {
        jack_status_t st {};
        client_ = jack_client_open("rec", JackNoStartServer, &st);
        if (!client_) return;
        rate_ = jack_get_sample_rate(client_);
        capacity_ = static_cast<std::size_t>(seconds * rate_);
        for (int k = 1; k <= channels; ++k) {
            ports_.push_back(jack_port_register(client_, ("in_" + std::to_string(k)).c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsInput, 0));
            data_.emplace_back(capacity_, 0.0f);
        }
        cycles_.assign(capacity_ / 16 + 16, Cycle {});
        jack_set_process_callback(client_, &JackRecorder::process, this);
        ok_ = jack_activate(client_) == 0;
    }
    ~JackRecorder()
    {
        if (client_) {
            jack_deactivate(client_);
            jack_client_close(client_);
        }
    }
    bool ok() const noexcept { return ok_; }
    std::size_t frames() const noexcept { return frames_.load(std::memory_order_acquire); }
    double sampleRate() const noexcept { return static_cast<double>(rate_); }
    /// Channel k's samples so far (copy; call after the recording has stopped growing or anytime).
    std::vector<float> channel(int k) const
    {
        const std::size_t n = frames();
        return std::vector<float>(data_[static_cast<std::size_t>(k)].begin(), data_[static_cast<std::size_t>(k)].begin() + static_cast<long>(n));
    }
    /// Steady-clock seconds at which frame `f`'s period reached the recorder, plus the frame's
    /// place in the period.
    double frameTime(std::size_t f) const
    {
        const std::size_t n = cycleCount_.load(std::memory_order_acquire);
        std::size_t lo = 0, hi = n;   // the last cycle starting at or before f
        while (hi - lo > 1) {
            const std::size_t mid = (lo + hi) / 2;
            (cycles_[mid].frame <= f ? lo : hi) = mid;
        }
        return n == 0 ? 0.0 : cycles_[lo].time + static_cast<double>(f - cycles_[lo].frame) / static_cast<double>(rate_);
    }
    /// The ports connected to in_(k+1).
    std::vector<std::string> connections(int k) const
    {
        std::vector<std::string> names;
        if (const char** c = jack_port_get_all_connections(client_, ports_[static_cast<std::size_t>(k)])) {
            for (const char** p = c; *p; ++p) names.emplace_back(*p);
            jack_free(c);
        }
        return names;
    }

private:
    static int process(jack_nframes_t n, void* self)
    {
        auto& r = *static_cast<JackRecorder*>(self);
        const std::size_t at = r.frames_.load(std::memory_order_relaxed);
        const std::size_t len = std::min<std::size_t>(n, r.capacity_ - at);
        for (std::size_t c = 0; c < r.ports_.size(); ++c) {
            const auto* in = static_cast<const float*>(jack_port_get_buffer(r.ports_[c], n));
            std::copy(in, in + len, r.data_[c].begin() + static_cast<long>(at));
        }
        const std::size_t c = r.cycleCount_.load(std::memory_order_relaxed);
        if (len > 0 && c < r.cycles_.size()) {
            r.cycles_[c] = Cycle {at, std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count()};
            r.cycleCount_.store(c + 1, std::memory_order_release);
        }
        r.frames_.store(at + len, std::memory_order_release);
        return 0;
    }
    jack_client_t* client_ = nullptr;
    jack_nframes_t rate_ = 0;
    std::size_t capacity_ = 0;
    std::vector<jack_port_t*> ports_;
    std::vector<std::vector<float>> data_;
    std::atomic<std::size_t> frames_ {0};
    struct Cycle {
        std::size_t frame = 0;
        double time = 0.0;
    };
    std::vector<Cycle> cycles_;
    std::atomic<std::size_t> cycleCount_ {0};
    bool ok_ = false;
};

} // namespace armadillo::test
