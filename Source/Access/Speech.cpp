#include "Access/Speech.h"
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <fcntl.h>
#include <dlfcn.h>
#include <fstream>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace armadillo::access {

namespace {

/// speech-dispatcher through libspeechd, loaded at run time. Function types and the values of
/// SPD_MODE_SINGLE (0), SPD_MESSAGE (2) and SPD_IMPORTANT (1) as libspeechd.h / speechd_types.h
/// (speech-dispatcher 0.11) declare them.
class SpeechDispatcher final : public Speech {
public:
    static std::unique_ptr<Speech> open(std::string& why)
    {
        void* lib = ::dlopen("libspeechd.so.2", RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            why = "libspeechd.so.2 not found (Debian: libspeechd2)";
            return nullptr;
        }
        auto s = std::unique_ptr<SpeechDispatcher>(new SpeechDispatcher(lib));
        if (!s->open_ || !s->say_ || !s->cancel_ || !s->rate_ || !s->close_) {
            why = "libspeechd.so.2 lacks the expected functions";
            return nullptr;
        }
        s->connection_ = s->open_("armadillo", "main", nullptr, 0 /* SPD_MODE_SINGLE */);
        if (!s->connection_) {
            why = "no speech-dispatcher to talk to (is it installed and allowed to start?)";
            return nullptr;
        }
        return s;
    }
    ~SpeechDispatcher() override
    {
        if (connection_) close_(connection_);
        ::dlclose(lib_);
    }
    void say(const std::string& text, bool interrupt) override
    {
        if (interrupt) cancel_(connection_);
        say_(connection_, interrupt ? 1 /* SPD_IMPORTANT */ : 2 /* SPD_MESSAGE */, text.c_str());
    }
    void stop() override { cancel_(connection_); }
    void setRate(int rate) override { rate_(connection_, std::clamp(rate, -100, 100)); }
    std::string name() const override { return "speechd"; }

private:
    explicit SpeechDispatcher(void* lib) : lib_(lib)
    {
        open_ = reinterpret_cast<OpenFn>(::dlsym(lib, "spd_open"));
        say_ = reinterpret_cast<SayFn>(::dlsym(lib, "spd_say"));
        cancel_ = reinterpret_cast<ConnFn>(::dlsym(lib, "spd_cancel"));
        rate_ = reinterpret_cast<RateFn>(::dlsym(lib, "spd_set_voice_rate"));
        close_ = reinterpret_cast<CloseFn>(::dlsym(lib, "spd_close"));
    }
    using OpenFn = void* (*)(const char*, const char*, const char*, int);
    using SayFn = int (*)(void*, int, const char*);
    using ConnFn = int (*)(void*);
    using RateFn = int (*)(void*, int);
    using CloseFn = void (*)(void*);
    void* lib_ = nullptr;
    void* connection_ = nullptr;
    OpenFn open_ = nullptr;
    SayFn say_ = nullptr;
    ConnFn cancel_ = nullptr;
    RateFn rate_ = nullptr;
    CloseFn close_ = nullptr;
};

/// espeak-ng as a child process per utterance; a new utterance stops the one still speaking.
class EspeakProcess final : public Speech {
public:
    static std::unique_ptr<Speech> open(std::string& why)
    {
        // Found on PATH? (posix_spawnp would fail later anyway; say so up front.)
        auto s = std::make_unique<EspeakProcess>();
        if (!s->spawn("", true)) {
            why = "espeak-ng could not be started (Debian: espeak-ng)";
            return nullptr;
        }
        return s;
    }
    ~EspeakProcess() override
    {
        // The last words (a final status) are heard out, not cut off as the program ends.
        if (child_ > 0) ::waitpid(child_, nullptr, 0);
    }
    void say(const std::string& text, bool) override
    {
        stop();
        spawn(text, false);
    }
    void stop() override
    {
        if (child_ > 0) {
            ::kill(child_, SIGTERM);
            ::waitpid(child_, nullptr, 0);
            child_ = -1;
        }
    }
    void setRate(int rate) override
    {
        // espeak-ng -s: words per minute, 80..450, default 175. −100 → 80, 0 → 175, +100 → 350.
        const int r = std::clamp(rate, -100, 100);
        wpm_ = r < 0 ? 175 + r * 95 / 100 : 175 + r * 175 / 100;
    }
    std::string name() const override { return "espeak"; }

private:
    bool spawn(const std::string& text, bool probe)
    {
        const std::string speed = std::to_string(wpm_);
        std::vector<const char*> argv {"espeak-ng", "-s", speed.c_str()};
        if (probe) argv.push_back("--version");
        else {
            argv.push_back("--");
            argv.push_back(text.c_str());
        }
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
        pid_t pid = -1;
        const int rc = ::posix_spawnp(&pid, "espeak-ng", &actions, nullptr, const_cast<char* const*>(argv.data()), environ);
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0) return false;
        if (probe) {
            int status = 0;
            ::waitpid(pid, &status, 0);
            return WIFEXITED(status) && WEXITSTATUS(status) == 0;
        }
        child_ = pid;
        return true;
    }
    pid_t child_ = -1;
    int wpm_ = 175;
};

/// Every utterance as a line of a file: "say: TEXT", "say+: TEXT" (queued), "stop", "rate: N".
class CaptureSpeech final : public Speech {
public:
    explicit CaptureSpeech(const std::string& path) : out_(path, std::ios::app) {}
    bool ok() const { return static_cast<bool>(out_); }
    void say(const std::string& text, bool interrupt) override { out_ << (interrupt ? "say: " : "say+: ") << text << "\n" << std::flush; }
    void stop() override { out_ << "stop\n" << std::flush; }
    void setRate(int rate) override { out_ << "rate: " << rate << "\n" << std::flush; }
    std::string name() const override { return "capture"; }

private:
    std::ofstream out_;
};

} // namespace

std::unique_ptr<Speech> makeSpeech(const std::string& spec, std::string& why)
{
    if (spec == "none") return nullptr;
    if (spec.rfind("capture:", 0) == 0) {
        auto c = std::make_unique<CaptureSpeech>(spec.substr(8));
        if (!c->ok()) {
            why = "cannot write " + spec.substr(8);
            return nullptr;
        }
        return c;
    }
    if (spec == "speechd") return SpeechDispatcher::open(why);
    if (spec == "espeak") return EspeakProcess::open(why);
    if (spec == "auto") {
        std::string first;
        if (auto s = SpeechDispatcher::open(first)) return s;
        if (auto s = EspeakProcess::open(why)) return s;
        why = first + "; " + why;
        return nullptr;
    }
    why = "unknown speech backend '" + spec + "' (auto, speechd, espeak, capture:FILE, none)";
    return nullptr;
}

} // namespace armadillo::access
