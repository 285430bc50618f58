#include "Access/ReaderVoice.h"
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace armadillo::access {

namespace {
constexpr std::size_t kMaxQueued = 64;   // a flood of announcements keeps only the newest
}

ReaderVoice::ReaderVoice() : worker_([this] { run(); }) {}

ReaderVoice::~ReaderVoice()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        quit_ = true;
    }
    wake_.notify_all();
    worker_.join();
}

std::string ReaderVoice::open(const std::string& speechSpec, const std::string& displaySpec)
{
    std::string why, problems;
    auto speech = speechSpec.empty() || speechSpec == "none" ? nullptr : access::makeSpeech(speechSpec, why);
    if (! speechSpec.empty() && speechSpec != "none" && speech == nullptr) problems += "No speech (" + why + "). ";
    why.clear();
    auto display = displaySpec.empty() || displaySpec == "none" ? nullptr : access::makeBrailleDisplay(displaySpec, why);
    if (! displaySpec.empty() && displaySpec != "none" && display == nullptr) problems += "No braille display (" + why + "). ";
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return ! busy_; });   // the worker is not inside a backend
    ops_.clear();
    speech_ = std::move(speech);
    display_ = std::move(display);
    if (speech_) speech_->setRate(rate_);
    return problems;
}

void ReaderVoice::close()
{
    (void) open("none", "none");
}

bool ReaderVoice::speaking() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return speech_ != nullptr;
}

bool ReaderVoice::showing() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return display_ != nullptr;
}

void ReaderVoice::say(const std::string& text, bool interrupt)
{
    if (text.empty()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        last_ = text;
        if (speech_ == nullptr && display_ == nullptr) return;
        if (interrupt) dropQueuedSpeech();   // what was still waiting to be said is out of date
        if (ops_.size() >= kMaxQueued) ops_.pop_front();
        ops_.push_back({Op::Kind::Say, text, interrupt, 0});
    }
    wake_.notify_all();
}

void ReaderVoice::dropQueuedSpeech()
{
    // Only texts: a rate change queued before them still applies.
    ops_.erase(std::remove_if(ops_.begin(), ops_.end(), [](const Op& op) { return op.kind == Op::Kind::Say; }), ops_.end());
}

void ReaderVoice::repeat()
{
    std::string text;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        text = last_;
    }
    say(text.empty() ? std::string("Nothing was said yet.") : text, true);
}

void ReaderVoice::stop()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        dropQueuedSpeech();
        ops_.push_back({Op::Kind::Stop, {}, true, 0});
    }
    wake_.notify_all();
}

void ReaderVoice::setRate(int rate)
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        rate_ = rate < -100 ? -100 : (rate > 100 ? 100 : rate);
        ops_.push_back({Op::Kind::Rate, {}, false, rate_});
    }
    wake_.notify_all();
}

int ReaderVoice::rate() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return rate_;
}

std::string ReaderVoice::lastSaid() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return last_;
}

std::string ReaderVoice::takeKeys()
{
    std::lock_guard<std::mutex> lock(mutex_);
    std::string k;
    k.swap(keys_);
    return k;
}

void ReaderVoice::waitIdle()
{
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return ops_.empty() && ! busy_; });
}

void ReaderVoice::run()
{
    std::unique_lock<std::mutex> lock(mutex_);
    while (! quit_) {
        if (ops_.empty()) {
            // A display's keys are polled while nothing is to be said (BrlAPI readKey does not block).
            if (display_ != nullptr && display_->fd() >= 0) {
                const auto key = display_->readKey();
                if (! key.empty() && keys_.size() < 256) keys_ += key;
                if (! key.empty()) continue;
                wake_.wait_for(lock, std::chrono::milliseconds(50));
            } else {
                wake_.wait(lock);
            }
            continue;
        }
        Op op = std::move(ops_.front());
        ops_.pop_front();
        busy_ = true;
        auto* speech = speech_.get();
        auto* display = display_.get();
        // The backends are called outside the lock (they may block), so say() never waits on them;
        // open() waits for busy_ to clear before it replaces them.
        lock.unlock();
        switch (op.kind) {
        case Op::Kind::Say:
            if (speech) speech->say(op.text, op.interrupt);
            if (display) display->write(op.text);
            break;
        case Op::Kind::Stop:
            if (speech) speech->stop();
            break;
        case Op::Kind::Rate:
            if (speech) speech->setRate(op.rate);
            break;
        }
        lock.lock();
        busy_ = false;
        idle_.notify_all();   // open() waits for !busy_, waitIdle() for an empty queue too
    }
    busy_ = false;
    idle_.notify_all();
}

bool ReaderVoice::readerDetected(const std::string& procDir, const std::vector<std::string>& sockets)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    for (const auto& s : sockets)
        if (! s.empty() && fs::exists(s, ec)) return true;
    fs::directory_iterator it(procDir, ec), end;
    for (; ! ec && it != end; it.increment(ec)) {
        std::ifstream comm(it->path() / "comm");
        std::string name;
        if (comm && std::getline(comm, name) && (name == "orca" || name == "brltty" || name == "speech-dispatch"
                                                  || name == "speech-dispatcher"))
            return true;
    }
    return false;
}

std::vector<std::string> ReaderVoice::defaultSockets()
{
    // BrlAPI's local sockets live in BRLAPI_SOCKETPATH (/var/lib/BrlAPI in brltty's brlapi.h;
    // one socket per server, named by its number); speech-dispatcher's in
    // $XDG_RUNTIME_DIR/speech-dispatcher/speechd.sock (its default unix socket).
    std::vector<std::string> out;
    std::error_code ec;
    for (const char* dir : {"/var/lib/BrlAPI", "/run/brltty"})
        for (std::filesystem::directory_iterator it(dir, ec), end; ! ec && it != end; it.increment(ec))
            out.push_back(it->path().string());
    if (const char* xdg = std::getenv("XDG_RUNTIME_DIR"); xdg != nullptr && *xdg != '\0')
        out.push_back(std::string(xdg) + "/speech-dispatcher/speechd.sock");
    return out;
}

} // namespace armadillo::access
