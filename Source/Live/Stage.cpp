#include "Live/Stage.h"

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

bool Stage::handleMidi(const std::uint8_t* bytes, int size) noexcept
{
    if (bytes == nullptr || size < 2) return false;
    const int status = bytes[0] & 0xF0;
    const int data1 = bytes[1] & 0x7F;
    if (status == 0xC0) {   // program change: 2 bytes
        cue(data1);
        return true;
    }
    if (size < 3) return false;
    const int data2 = bytes[2] & 0x7F;
    if (status == 0x90 && data2 > 0) {   // a note-on with velocity 0 is a note-off
        if (data1 == nextNote_.load(std::memory_order_relaxed)) {
            next();
            return true;
        }
        if (data1 == prevNote_.load(std::memory_order_relaxed)) {
            previous();
            return true;
        }
        return false;
    }
    if (status == 0xB0 && data1 == kPanicCc) {
        panic();
        return true;
    }
    if (status == 0xB0 && data1 == kResumeCc && data2 >= 64) {
        resume();
        return true;
    }
    return false;
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
