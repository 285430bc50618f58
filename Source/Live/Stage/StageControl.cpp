#include "Live/Stage/StageControl.h"
#include "Core/Errors.h"
#include "Osc/OscIo.h"
#include <algorithm>
#include <arpa/inet.h>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>
#include <vector>

namespace armadillo::live {

static_assert(sizeof(termios) <= 128, "KeyReader::saved_ must hold a termios");

bool stageCommandFromOsc(const osc::OscMessage& m, core::StageCommand& out, std::string& why)
{
    const std::string_view a = m.address;
    if (a == "/armadillo/panic") out = {core::StageCommand::Kind::Panic, 0};
    else if (a == "/armadillo/resume") out = {core::StageCommand::Kind::Resume, 0};
    else if (a == "/armadillo/cue/next") out = {core::StageCommand::Kind::CueNext, 0};
    else if (a == "/armadillo/cue/prev") out = {core::StageCommand::Kind::CuePrev, 0};
    else if (a == "/armadillo/cue") {
        double v = 0.0;
        if (m.count != 1 || !m.args[0].asNumber(v) || !(v >= 0.0) || v > 9999.0 || std::floor(v) != v) {
            why = "/armadillo/cue needs one whole number >= 0 (the cue's index)";
            return false;
        }
        out = {core::StageCommand::Kind::CueGoto, static_cast<int>(v)};
    } else {
        why = "not a stage command: " + std::string(a);
        return false;
    }
    return true;
}

bool stageCommandFromKey(char key, core::StageCommand& out)
{
    switch (key) {
    case 'p': case 'P': case 27: out = {core::StageCommand::Kind::Panic, 0}; return true;
    case 'r': case 'R': out = {core::StageCommand::Kind::Resume, 0}; return true;
    case 'n': case 'N': case ' ': out = {core::StageCommand::Kind::CueNext, 0}; return true;
    case 'b': case 'B': out = {core::StageCommand::Kind::CuePrev, 0}; return true;
    default:
        if (key >= '0' && key <= '9') {
            out = {core::StageCommand::Kind::CueGoto, key - '0'};
            return true;
        }
        return false;
    }
}

std::string describe(const core::StageCommand& c)
{
    switch (c.kind) {
    case core::StageCommand::Kind::Panic: return "panic";
    case core::StageCommand::Kind::Resume: return "resume";
    case core::StageCommand::Kind::CueNext: return "next cue";
    case core::StageCommand::Kind::CuePrev: return "previous cue";
    case core::StageCommand::Kind::CueGoto: return "cue " + std::to_string(c.cue);
    }
    return "?";
}

StageControlReceiver::StageControlReceiver(int port, Handler handler, const StageControlListen& listen)
    : listen_(listen), handler_(std::move(handler))
{
    fd_ = osc::bindUdp(listen_.bind, port, "--control-in", port_);
    sockaddr_storage bound {};
    socklen_t len = sizeof bound;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len);
    boundAddress_ = osc::addressName(reinterpret_cast<const sockaddr*>(&bound));
}

std::vector<std::string> StageControlReceiver::takeRefusals()
{
    std::lock_guard<std::mutex> lock(refusalsMutex_);
    std::vector<std::string> out;
    out.swap(newRefusals_);
    return out;
}

std::string StageControlReceiver::summaryJson() const
{
    return ",\"control_commands\":" + std::to_string(commands()) + ",\"control_refused\":" + std::to_string(refused()) +
           ",\"control_not_allowed\":" + std::to_string(notAllowed());
}

void StageControlReceiver::handleFrom(const sockaddr* sender, const std::uint8_t* data, std::size_t size)
{
    if (listen_.allow.allows(sender)) {
        handleDatagram(data, size);
        return;
    }
    notAllowed_.fetch_add(1);
    const std::string name = osc::addressName(sender);
    std::lock_guard<std::mutex> lock(refusalsMutex_);
    if (refusedSenders_.size() >= 64 || std::find(refusedSenders_.begin(), refusedSenders_.end(), name) != refusedSenders_.end()) return;
    refusedSenders_.push_back(name);
    newRefusals_.push_back("refused stage control from " + name + " (not in " + listen_.allowName + ")");
}

StageControlReceiver::~StageControlReceiver()
{
    stop();
    if (fd_ >= 0) ::close(fd_);
}

void StageControlReceiver::start()
{
    if (thread_.joinable()) return;
    stop_.store(false);
    thread_ = std::thread([this] { run(); });
}

void StageControlReceiver::stop()
{
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

void StageControlReceiver::handleDatagram(const std::uint8_t* data, std::size_t size)
{
    std::string error;
    const bool ok = osc::decodeOscPacket(
        data, size,
        [this](const osc::OscMessage& m) {
            if (m.address == "/armadillo/message") {
                double priority = 0.0;
                const bool valid = textHandler_ && m.count >= 1 && m.count <= 2 && m.args[0].type == 's' &&
                                (m.count == 1 || m.args[1].asNumber(priority));
                if (!valid) {
                    refused_.fetch_add(1);
                    return;
                }
                commands_.fetch_add(1);
                textHandler_(std::string(m.args[0].bytes), priority >= 1.0 ? 1 : 0);
                return;
            }
            core::StageCommand c;
            std::string why;
            if (!stageCommandFromOsc(m, c, why)) {
                refused_.fetch_add(1);
                return;
            }
            commands_.fetch_add(1);
            if (handler_) handler_(c);
        },
        &error);
    if (!ok) refused_.fetch_add(1);
}

void StageControlReceiver::run()
{
    std::vector<std::uint8_t> buffer(65536);
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p {fd_, POLLIN, 0};
        if (::poll(&p, 1, 20) <= 0) continue;
        sockaddr_storage from {};
        socklen_t fromLength = sizeof from;
        const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from), &fromLength);
        if (n > 0) handleFrom(reinterpret_cast<const sockaddr*>(&from), buffer.data(), static_cast<std::size_t>(n));
    }
}

KeyReader::KeyReader(int fd, Handler handler) : fd_(fd), handler_(std::move(handler))
{
    termios t {};
    if (::isatty(fd_) == 1 && ::tcgetattr(fd_, &t) == 0) {
        std::memcpy(saved_, &t, sizeof t);
        restore_ = true;
        t.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
        t.c_cc[VMIN] = 0;
        t.c_cc[VTIME] = 0;
        ::tcsetattr(fd_, TCSANOW, &t);
    }
}

KeyReader::~KeyReader() { stop(); }

void KeyReader::start()
{
    if (thread_.joinable()) return;
    stop_.store(false);
    thread_ = std::thread([this] { run(); });
}

void KeyReader::stop()
{
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    if (restore_) {
        termios t {};
        std::memcpy(&t, saved_, sizeof t);
        ::tcsetattr(fd_, TCSANOW, &t);
        restore_ = false;
    }
}

void KeyReader::run()
{
    while (!stop_.load(std::memory_order_relaxed)) {
        pollfd p {fd_, POLLIN, 0};
        const int r = ::poll(&p, 1, 20);
        if (r <= 0) continue;
        char c = 0;
        const ssize_t n = ::read(fd_, &c, 1);
        if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) break;   // stdin ended
        if (n != 1) continue;
        core::StageCommand command;
        if (stageCommandFromKey(c, command) && handler_) handler_(command);
    }
}

} // namespace armadillo::live
