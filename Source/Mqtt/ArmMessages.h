#pragma once
// Messages shown on the arm (issue 35, docs/MQTT.md): takes the inbox's messages one at a time,
// lays each out in Arm Braille off the control thread (Braille/BrailleScene.h's
// prepareArmMessage: the reader's grade and method) and hands it to the braille scene, which shows
// it through its own motor intents, so every level passes the tactile engine's safety stage. An
// urgent message goes at once (the scene interrupts the one showing, which is shown again from its
// start afterwards); the others wait until the scene is free, so three messages published
// together are shown in order.
//
// One thread (the command line's main loop, the app's message thread) owns a presenter and calls
// poll() regularly. The messages handed to the scene are owned here until the scene gives their
// id back: destroy the presenter only after the scene has stopped running (or is gone).
#include "Braille/BrailleScene.h"
#include "Mqtt/MessageInbox.h"
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace armadillo::mqtt {

struct PresenterOptions {
    bool timed = false;      ///< true: drawn with the passive timings, framed; false: read by roll
    int grade = 1;           ///< 1 or 2
    braille::DisplayMethod method = braille::DisplayMethod::Rows;
    /// Sign shorthand (thesis §5.3, Braille/Training.h signShorthand): a whole word of a message
    /// equal to one of these words (ASCII case ignored) is shown as its shorthand ("exit" → "ex").
    /// Pairs (shorthand, word), as signShorthand() gives them.
    std::vector<std::pair<std::string, std::string>> shorthand;
};

/// `text` with each word found in `shorthand` (pairs (shorthand, word)) replaced by its short form.
std::string applyShorthand(const std::string& text, const std::vector<std::pair<std::string, std::string>>& shorthand);

class MessagePresenter {
public:
    MessagePresenter(MessageInbox& inbox, PresenterOptions options);

    /// What happened since the last poll, in words for the reader's log ("message 3 from
    /// 'arm/inbox' on the arm: ..."). Hands the next message over when the scene is free.
    std::vector<std::string> poll(braille::BrailleSceneControls& scene);

    std::size_t onArm() const noexcept { return handed_.size(); }   ///< handed over, not yet given back
    std::uint64_t shown() const noexcept { return shown_; }          ///< given back by the scene
    std::uint64_t unshowable() const noexcept { return unshowable_; }///< refused by the braille translation

private:
    bool handOver(braille::BrailleSceneControls& scene, const InboxMessage& m, std::vector<std::string>& said);

    MessageInbox& inbox_;
    PresenterOptions options_;
    struct Handed {
        std::unique_ptr<braille::ArmMessage> prepared;
        InboxMessage message;
    };
    std::map<std::uint64_t, Handed> handed_;
    std::deque<InboxMessage> again_;   // interrupted by an urgent one: shown again, first
    std::uint64_t shown_ = 0, unshowable_ = 0;
};

} // namespace armadillo::mqtt
