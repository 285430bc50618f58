#include "Live/Stage/Stage.h"

namespace armadillo::live {

Stage::~Stage() = default;

bool Stage::offer(std::unique_ptr<live::CuePlayer>& player) noexcept
{
    if (! canOffer()) return false;   // the player stays the caller's
    std::unique_ptr<Slot> slot(new (std::nothrow) Slot(std::move(player)));   // message thread
    if (slot == nullptr) return false;
    return players_.offer(slot);
}

void Stage::replace(std::unique_ptr<live::CuePlayer> player) noexcept
{
    players_.replace(std::unique_ptr<Slot>(new (std::nothrow) Slot(std::move(player))));
}

void Stage::collect() noexcept
{
    players_.collect();
}

void Stage::panic() noexcept
{
    if (! panic_.exchange(true, std::memory_order_acq_rel)) panics_.fetch_add(1, std::memory_order_relaxed);
}

void Stage::resume() noexcept
{
    panic_.store(false, std::memory_order_release);
}

void Stage::apply(const core::StageCommand& c) noexcept
{
    using K = core::StageCommand::Kind;
    switch (c.kind) {
    case K::Panic: panic(); return;
    case K::Resume: resume(); return;
    case K::CueNext: next(); return;
    case K::CuePrev: previous(); return;
    case K::CueGoto: cue(c.cue); return;   // clamped to the list when applied
    }
}

bool Stage::commandFromMidi(const std::uint8_t* bytes, int size, core::StageCommand& out) const noexcept
{
    using K = core::StageCommand::Kind;
    if (bytes == nullptr || size < 2) return false;
    const int status = bytes[0] & 0xF0;
    const int data1 = bytes[1] & 0x7F;
    if (status == 0xC0) {   // program change: 2 bytes
        out = {K::CueGoto, data1};
        return true;
    }
    if (size < 3) return false;
    const int data2 = bytes[2] & 0x7F;
    if (status == 0x90 && data2 > 0) {   // a note-on with velocity 0 is a note-off
        if (data1 == nextNote_.load(std::memory_order_relaxed)) out = {K::CueNext, 0};
        else if (data1 == prevNote_.load(std::memory_order_relaxed)) out = {K::CuePrev, 0};
        else return false;
        return true;
    }
    if (status == 0xB0 && data1 == kPanicCc) out = {K::Panic, 0};
    else if (status == 0xB0 && data1 == kResumeCc && data2 >= 64) out = {K::Resume, 0};
    else return false;
    return true;
}

bool Stage::handleMidi(const std::uint8_t* bytes, int size) noexcept
{
    core::StageCommand c;
    if (!commandFromMidi(bytes, size, c)) return false;
    apply(c);
    return true;
}

live::CuePlayer* Stage::beginStep() noexcept
{
    players_.takeOffered();   // the replaced player goes back to the message thread (collect)
    auto* player = cues();
    const int index = goto_.exchange(-1, std::memory_order_acq_rel);
    const int delta = delta_.exchange(0, std::memory_order_acq_rel);
    if (player != nullptr) {
        if (index >= 0) player->request(index);
        if (delta != 0) player->request(player->requested() + delta);
    }
    return player;
}

} // namespace armadillo::live
