#include "Plugin/PerkinsKeys.h"
#include "Access/Chords.h"
#include "Access/ReaderVoice.h"
#include <cctype>

namespace armadillo::plugin {

void TrainingKeys::attach(juce::TextEditor& answer, std::function<void()> submit,
                          std::function<void(const juce::String&)> announce, access::ReaderVoice* voice)
{
    answer_ = &answer;
    voice_ = voice;
    answer.addKeyListener(this);
    onLetter = [this, announce](char c) {
        answer_->insertTextAtCaret(juce::String::charToString(static_cast<juce::juce_wchar>(c)));
        announce(juce::String::charToString(static_cast<juce::juce_wchar>(c)));   // the echo a braille reader expects
    };
    onErase = [this, announce] {
        const auto text = answer_->getText();
        answer_->setText(text.dropLastCharacters(1), false);
        announce(text.isEmpty() ? juce::String("nothing to erase") : "erased " + text.getLastCharacters(1));
    };
    onSubmit = submit;
    onSay = [announce](const std::string& text) { announce(juce::String(text)); };
    onRepeat = [this] {
        if (voice_ != nullptr) voice_->repeat();
    };
    onStop = [this] {
        if (voice_ != nullptr) voice_->stop();
    };
}

void TrainingKeys::pollDisplay()
{
    if (voice_ == nullptr || answer_ == nullptr) return;
    for (const char c : voice_->takeKeys()) {
        if (c == '\n') {
            if (onSubmit) onSubmit();
        } else if (c == '\b') {
            if (onErase) onErase();
        } else if (static_cast<unsigned char>(c) >= ' ') {
            answer_->insertTextAtCaret(juce::String::charToString(static_cast<juce::juce_wchar>(c)));
        }
    }
}

void TrainingKeys::setChordMode(bool on)
{
    chordMode_ = on;
    chords_.reset();
    down_.clear();
    if (onSay) onSay(on ? "Chord entry on: S D F J K L are dots 3 2 1 4 5 6, press together, Space answers."
                        : "Chord entry off: type letters, Return answers.");
}

bool TrainingKeys::keyPressed(const juce::KeyPress& key, juce::Component*)
{
    const int code = key.getKeyCode();
    if (code == juce::KeyPress::F2Key) {
        setChordMode(! chordMode_);
        return true;
    }
    if (code == juce::KeyPress::F3Key) {
        if (onRepeat) onRepeat();
        return true;
    }
    if (code == juce::KeyPress::F4Key) {
        if (onStop) onStop();
        return true;
    }
    if (! chordMode_ || key.getModifiers().isCtrlDown() || key.getModifiers().isAltDown()) return false;
    const auto c = static_cast<char>(key.getTextCharacter() != 0 ? key.getTextCharacter() : code);
    if (access::PerkinsChords::isChordKey(c)) {
        const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (chords_.down(lower) && down_.find(lower) == std::string::npos) down_ += lower;
        return true;   // never typed into the field as a letter
    }
    if (code == juce::KeyPress::spaceKey) {
        if (onSubmit) onSubmit();
        return true;
    }
    if (code == juce::KeyPress::backspaceKey) {
        if (onErase) onErase();
        return true;
    }
    // Any other printable key in chord mode is refused (a stray letter would spoil the answer).
    if (key.getTextCharacter() >= ' ') {
        if (onSay) onSay("Chord mode: use S D F J K L, Space to answer, F2 to type letters.");
        return true;
    }
    return false;
}

bool TrainingKeys::keyStateChanged(bool isKeyDown, juce::Component*)
{
    if (! chordMode_ || isKeyDown || down_.empty()) return false;
    bool used = false;
    for (std::size_t i = 0; i < down_.size();) {
        const char k = down_[i];
        const int upper = std::toupper(static_cast<unsigned char>(k));
        if (isDown(k) || isDown(upper)) {
            ++i;
            continue;
        }
        down_.erase(i, 1);
        used = true;
        const auto e = chords_.up(k);
        if (e.kind == access::PerkinsChords::Event::Kind::Letter) {
            if (onLetter) onLetter(e.letter);
        } else if (e.kind == access::PerkinsChords::Event::Kind::NotLetter) {
            if (onSay) onSay(e.why);
        }
    }
    return used;
}

} // namespace armadillo::plugin
