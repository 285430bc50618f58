#pragma once
// Answers without sight in the app's Training panel (issue 26): Perkins chord entry on an
// ordinary keyboard, the app's counterpart of the CLI's --chords (Access/Chords.h). The six keys
// S D F J K L are dots 3 2 1 4 5 6 and are pressed TOGETHER, as on a Perkins brailler: the cell is
// the set of chord keys that were down at any moment since the first went down, and it is taken
// when the last one comes up. Space submits the answer, Backspace takes back the last cell.
//
// The chord itself is access::PerkinsChords (Access/Chords.h, JUCE-free, tested in tests_access);
// TrainingKeys is the JUCE KeyListener the Training panel puts on its answer field: F2 turns
// chord entry on and off (off = letters are typed as usual), F3 repeats what was last said, F4
// stops speech. Keys the listener does not use fall through to the field. Threads: message
// thread only.
#include "Access/Chords.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <functional>
#include <string>

namespace armadillo::access {
class ReaderVoice;
}

namespace armadillo::plugin {

class TrainingKeys : public juce::KeyListener {
public:
    /// Wires the keys to a panel's answer field: chord letters are inserted (and echoed), Space
    /// and Return submit, F3/F4 go to `voice` (may be null). Adds itself as the field's key listener.
    void attach(juce::TextEditor& answer, std::function<void()> submit, std::function<void(const juce::String&)> announce,
                access::ReaderVoice* voice);
    /// Timer: keys typed on the braille display answer as typed letters do ("\n" submits,
    /// "\b" erases).
    void pollDisplay();

    std::function<void(char letter)> onLetter;          ///< a chord that is a letter: add it
    std::function<void()> onErase;                      ///< Backspace in chord mode
    std::function<void()> onSubmit;                     ///< Space in chord mode
    std::function<void(const std::string&)> onSay;      ///< what to say (mode changes, bad chords, echo)
    std::function<void()> onRepeat, onStop;             ///< F3, F4
    /// Whether a key is held now; tests replace it (juce::KeyPress::isKeyCurrentlyDown by default).
    std::function<bool(int keyCode)> isDown = [](int code) { return juce::KeyPress::isKeyCurrentlyDown(code); };

    bool chordMode() const noexcept { return chordMode_; }
    void setChordMode(bool on);

    bool keyPressed(const juce::KeyPress& key, juce::Component* origin) override;
    bool keyStateChanged(bool isKeyDown, juce::Component* origin) override;

private:
    juce::TextEditor* answer_ = nullptr;
    access::ReaderVoice* voice_ = nullptr;
    bool chordMode_ = false;
    access::PerkinsChords chords_;
    std::string down_;            ///< chord keys seen down and not yet seen up
};

} // namespace armadillo::plugin
