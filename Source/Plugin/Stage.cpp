#include "Plugin/Stage.h"

namespace armadillo::plugin {

Stage::~Stage()
{
    delete pending_.exchange(nullptr);
    delete retired_.exchange(nullptr);
    delete active_;
}

bool Stage::offer(std::unique_ptr<live::CuePlayer>& player) noexcept
{
    if (! canOffer()) return false;
    auto* slot = new (std::nothrow) Slot(std::move(player));   // message thread
    if (slot == nullptr) return false;
    newest_ = slot->get();
    pending_.store(slot, std::memory_order_release);
    return true;
}

void Stage::replace(std::unique_ptr<live::CuePlayer> player) noexcept
{
    delete pending_.exchange(nullptr);
    delete retired_.exchange(nullptr);
    delete active_;
    active_ = new (std::nothrow) Slot(std::move(player));
    newest_ = active_ != nullptr ? active_->get() : nullptr;
}

void Stage::collect() noexcept
{
    delete retired_.exchange(nullptr, std::memory_order_acq_rel);
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
    if (auto* offered = pending_.exchange(nullptr, std::memory_order_acq_rel)) {
        retired_.store(active_, std::memory_order_release);   // offer() waits until it is collected
        active_ = offered;
    }
    auto* player = cues();
    const int index = goto_.exchange(-1, std::memory_order_acq_rel);
    const int delta = delta_.exchange(0, std::memory_order_acq_rel);
    if (player != nullptr) {
        if (index >= 0) player->request(index);
        if (delta != 0) player->request(player->requested() + delta);
    }
    return player;
}

} // namespace armadillo::plugin
