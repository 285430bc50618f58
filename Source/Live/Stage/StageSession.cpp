#include "Live/Stage/StageSession.h"
#include "Core/AtomicFile.h"
#include <exception>
#include <filesystem>

namespace armadillo::live {

StageSession::~StageSession()
{
    if (osc_ != nullptr) osc_->stop();
}

std::unique_ptr<CuePlayer> StageSession::build(const std::string& text, const std::string& name, const CueBuild& b) const
{
    return std::make_unique<CuePlayer>(parseSetList(text, name), b.base, b.motors, b.twoArms, b.gains);   // every cue's engine, prepared now
}

void StageSession::offer(std::unique_ptr<CuePlayer> player)
{
    // One hand-over in flight: a newer set list waits for the timer.
    waiting_ = std::move(player);
    waitingSet_ = true;
    stage_.collect();
    if (stage_.offer(waiting_)) waitingSet_ = false;
}

std::string StageSession::use(const std::string& text, const std::string& name, const CueBuild& b, std::string& summary)
{
    if (text.size() > kMaxSetListBytes) return name + ": the set list is longer than " + std::to_string(kMaxSetListBytes) + " bytes";
    std::unique_ptr<CuePlayer> player;
    try {
        player = build(text, name, b);
    } catch (const std::exception& e) {
        return e.what();
    }
    summary = "Set list " + name + ": " + std::to_string(player->cueCount()) + " cues, cue 1 '" + player->cue(0).name + "' (" + player->cue(0).scene + ")";
    std::lock_guard<std::mutex> lock(mutex_);
    builtRate_ = b.base.sampleRate;
    name_ = name;
    offer(std::move(player));
    reportedCue_ = 0;
    return {};
}

std::string StageSession::readFile(const std::string& path, std::string& text)
{
    std::error_code ec;
    if (! std::filesystem::is_regular_file(path, ec)) return "no such file: " + path;
    if (std::filesystem::file_size(path, ec) > kMaxSetListBytes) return path + " is too large to be a set list";
    try {
        text = core::readWholeFile(path);
    } catch (const std::exception&) {
        return "cannot read " + path;
    }
    return {};
}

void StageSession::clear()
{
    std::lock_guard<std::mutex> lock(mutex_);
    offer(nullptr);
    builtRate_ = 0.0;
    name_.clear();
    reportedCue_ = -1;
}

bool StageSession::loaded() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return waitingSet_ ? waiting_ != nullptr : stage_.newest() != nullptr;
}

std::unique_ptr<CuePlayer> StageSession::rebuild(const std::string& text, const std::string& name, const CueBuild& b, std::string& why)
{
    std::lock_guard<std::mutex> lock(mutex_);
    if (text.empty() || builtRate_ == b.base.sampleRate) return nullptr;
    try {
        auto player = build(text, name, b);
        builtRate_ = b.base.sampleRate;
        name_ = name;
        return player;
    } catch (const std::exception& e) {
        why = e.what();
        return nullptr;
    }
}

void StageSession::install(std::unique_ptr<CuePlayer> player)
{
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_.reset();
    waitingSet_ = false;
    stage_.replace(std::move(player));
}

StageSession::Report StageSession::tick()
{
    std::lock_guard<std::mutex> lock(mutex_);
    stage_.collect();   // the player the control side gave up is deleted here, never on the audio thread
    if (waitingSet_ && stage_.offer(waiting_)) waitingSet_ = false;
    Report r;
    if (osc_ != nullptr) r.refused = osc_->takeRefusals();
    const bool panicked = stage_.panicked();
    const auto count = stage_.panics();
    r.panicked = panicked && (! reportedPanicked_ || count != reportedPanics_);
    r.resumed = ! panicked && reportedPanicked_;
    reportedPanicked_ = panicked;
    reportedPanics_ = count;
    if (auto* player = stage_.newest(); player != nullptr && ! waitingSet_) {
        const int cue = player->current();
        if (cue != reportedCue_ && reportedCue_ >= 0) {
            const Cue& c = player->cue(cue);
            r.cue = "Cue " + std::to_string(cue + 1) + " of " + std::to_string(player->cueCount()) + ": '" + c.name + "' (" + c.scene + ")";
        }
        reportedCue_ = cue;
    }
    return r;
}

StageSession::Info StageSession::info() const
{
    Info info;
    info.panicked = stage_.panicked();
    info.panics = stage_.panics();
    std::lock_guard<std::mutex> lock(mutex_);
    const CuePlayer* player = waitingSet_ ? waiting_.get() : stage_.newest();
    if (player == nullptr) return info;
    info.setList = true;
    info.listName = name_;
    info.cueCount = player->cueCount();
    info.cue = waitingSet_ ? 0 : player->current();
    info.cueName = player->cue(info.cue).name;
    info.cueScene = player->cue(info.cue).scene;
    if (info.cue + 1 < info.cueCount) {
        info.next = info.cue + 1;
        info.nextName = player->cue(info.next).name;
        info.nextScene = player->cue(info.next).scene;
    }
    return info;
}

std::string StageSession::listenFromSettings(const std::string& bind, const std::string& allow, StageControlListen& listen)
{
    listen = StageControlListen {};
    listen.allowName = "the allow-list";
    if (!bind.empty()) {
        if (!osc::isIpAddress(bind)) return "stage control address '" + bind + "' is not an IPv4 or IPv6 address";
        listen.bind = bind;
    }
    if (allow.find_first_not_of(" \t") != std::string::npos) {
        try {
            listen.allow = osc::AllowList::parse(allow);
        } catch (const std::invalid_argument& e) {
            return std::string("stage control allow-list: ") + e.what();
        }
    }
    return {};
}

std::string StageSession::setOsc(bool on, int port, const StageControlListen& listen)
{
    std::lock_guard<std::mutex> lock(mutex_);   // tick() takes the refusals on the same receiver
    const std::string allow = listen.allow.describe();
    if (osc_ != nullptr && on && (port == 0 || osc_->port() == port) && listen.bind == oscBind_ && allow == oscAllow_) return {};
    if (osc_ != nullptr) osc_->stop();
    osc_.reset();
    if (! on) return {};
    try {
        // StageControl.h: /armadillo/panic, /armadillo/resume, /armadillo/cue/next|prev,
        // /armadillo/cue i, as `armadillo play --control-in` takes them. Its own thread: atomics only.
        osc_ = std::make_unique<StageControlReceiver>(port, [this](const core::StageCommand& c) { stage_.apply(c); }, listen);
        oscBind_ = listen.bind;
        oscAllow_ = allow;
        osc_->start();
    } catch (const std::exception& e) {
        osc_.reset();
        return e.what();
    }
    return {};
}

int StageSession::oscPort() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return osc_ != nullptr ? osc_->port() : 0;
}

} // namespace armadillo::live
