#include "Plugin/PerkinsKeys.h"
#include "Access/Chords.h"
#include "Access/ReaderVoice.h"
#include <cctype>

namespace armadillo::plugin {

namespace {
/// S D F J K L = dots 3 2 1 4 5 6 (the layout of Access/Chords.h); 0 for any other key.
int dotOf(char key) noexcept
{
    switch (std::tolower(static_cast<unsigned char>(key))) {
    case 'f': return 1;
    case 'd': return 2;
    case 's': return 3;
    case 'j': return 4;
    case 'k': return 5;
    case 'l': return 6;
    default: return 0;
    }
}
} // namespace

bool PerkinsChords::isChordKey(char key) noexcept { return dotOf(key) != 0; }

bool PerkinsChords::down(char key)
{
    const int d = dotOf(key);
    if (d == 0) return false;
    held_ |= 1u << (d - 1);
    chord_ = static_cast<braille::Dots>(chord_ | (1u << (d - 1)));
    return true;
}

PerkinsChords::Event PerkinsChords::up(char key)
{
    Event e;
    const int d = dotOf(key);
    if (d == 0 || (held_ & (1u << (d - 1))) == 0) return e;
    held_ &= ~(1u << (d - 1));
    if (held_ != 0 || chord_ == 0) return e;
    e.dots = chord_;
    chord_ = 0;
    // The letter of the cell through the same table the CLI's chords use (liblouis Grade 1).
    std::string keys;
    for (int dot = 1; dot <= 6; ++dot)
        if (e.dots & (1u << (dot - 1))) keys += "fdsjkl"[dot - 1];
    std::string letters, why;
    if (access::chordsToLetters(keys, letters, why) && letters.size() == 1) {
        e.kind = Event::Kind::Letter;
        e.letter = letters[0];
    } else {
        e.kind = Event::Kind::NotLetter;
        e.why = "dots " + braille::dotNumbers(e.dots) + " is not a letter";
    }
    return e;
}

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
    if (PerkinsChords::isChordKey(c)) {
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
        if (e.kind == PerkinsChords::Event::Kind::Letter) {
            if (onLetter) onLetter(e.letter);
        } else if (e.kind == PerkinsChords::Event::Kind::NotLetter) {
            if (onSay) onSay(e.why);
        }
    }
    return used;
}

} // namespace armadillo::plugin
