#include "Plugin/TrainingPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cmath>
#include <ctime>
#include <iostream>

namespace armadillo::plugin {

namespace {
constexpr int kMaxTypedCharacters = 1024;   // a pasted book stops here; the feeder refuses > 63 bytes anyway
const char* const kTypeHere = "type the answer, then Return";
const char* const kHint = "Feel what the arm shows, type the answer, press Return.";
const char* const kKeys = "Keys: Return sends (Backspace corrects first); F2 Perkins chords (S D F J K L, Space answers); "
                          "F5 repeats the prompt; F6 skips (counts as wrong); F8 stops the training; F3 says it again, "
                          "F4 hushes; Escape leaves the panel; Tab stays inside it. In the hold stage a push of the forearm "
                          "along its axis and back answers here.";
} // namespace

TrainingPanel::TrainingPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    mode_ = processor_.parameters().getRawParameterValue("braille.mode");
    setTitle("Braille training");
    setDescription("The braille training of thesis section 4.4.1: feel what the arm shows, type the answer, press Return.");
    // While the training runs the panel keeps Tab inside itself (Escape leaves it).
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);
    setWantsKeyboardFocus(true);   // Tab reaches the panel; focusGained passes it on inside

    heading_.setText("Braille training", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    describe(heading_, "Braille training", "The braille scene's training mode: one trial after another.");
    // A label's accessible name is its text: a screen reader reads the trial, prompt and result.
    describe(trial_, "Training trial", "Which trial this is, of how many.");
    describe(prompt_, "Training prompt", "What to feel for and answer in this trial.");
    describe(score_, "Training score", "How many answers were correct so far.");
    describe(result_, "Training result", "Whether the last answer was correct, or why it was not sent.");
    describe(tally_, "Results per answer", "For each expected answer (a side, a letter, a word): correct of asked.");
    describe(keys_, "Training keys", kKeys);
    keys_.setText(kKeys, juce::dontSendNotification);
    keys_.setColour(juce::Label::textColourId, juce::Colours::lightgrey);
    tally_.setColour(juce::Label::textColourId, juce::Colour(0xffb8d8b0));
    tally_.setMinimumHorizontalScale(0.6f);   // a long session's list squeezes before it is cut
    prompt_.setJustificationType(juce::Justification::centredLeft);
    prompt_.setMinimumHorizontalScale(0.8f);
    score_.setJustificationType(juce::Justification::centredRight);
    result_.setColour(juce::Label::textColourId, juce::Colour(0xffffc870));

    describe(answer_, "Answer",
             "Your answer to the current trial: left, right or both; here; a letter; the alphabet; or a word. Return sends it.");
    answer_.setTextToShowWhenEmpty(kTypeHere, juce::Colours::grey);
    answer_.setInputRestrictions(kMaxTypedCharacters);
    answer_.setReturnKeyStartsNewLine(false);
    answer_.onReturnKey = [this] { submit(); };
    chordKeys_.attach(answer_, [this] { submit(); }, [this](const juce::String& t) { announce(t); }, &processor_.voice());
    describe(answerButton_, "Answer", "Send the answer in the field (the same as Return).");
    answerButton_.onClick = [this] { submit(); };
    describe(save_, "Save training log", "Write the training log (CSV, one row per event) to a file.");
    save_.onClick = [this] { save(); };
    describe(repeat_, "Repeat the prompt", "Says the current trial's prompt again (F5).");
    repeat_.onClick = [this] { repeatPrompt(); };
    describe(skip_, "Skip this trial", "Goes on to the next trial; the skipped one counts as wrong (F6).");
    skip_.onClick = [this] { skip(); };
    describe(stop_, "Stop the training", "Ends the training: the braille scene goes back to active reading (F8).");
    stop_.onClick = [this] { stop(); };
    answer_.onEscapeKey = [this] { leave(); };

    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &trial_, &score_, &prompt_, &answer_,
                                                                        &answerButton_, &repeat_, &skip_, &stop_, &result_, &tally_, &keys_})
        addAndMakeVisible(*c);
    addChildComponent(save_);
    result_.setText(kHint, juce::dontSendNotification);
    startTimerHz(20);
}

TrainingPanel::~TrainingPanel()
{
    stopTimer();
    answer_.removeKeyListener(&chordKeys_);
}

void TrainingPanel::timerCallback()
{
    if (wanted_ && ! complete_) chordKeys_.pollDisplay();
    follow();
}

void TrainingPanel::follow()
{
    const auto& scenes = processor_.sceneTable().scenes;
    const int index = processor_.sceneIndex();
    const bool brailleChosen = index >= 0 && index < static_cast<int>(scenes.size())
                               && scenes[static_cast<std::size_t>(index)].scene == "braille";
    const bool trainingMode = mode_ != nullptr
                              && std::lround(mode_->load(std::memory_order_relaxed)) == static_cast<long>(braille::BrailleMode::Training);
    std::vector<braille::TrainingNotice> notices;
    int trial = 0, count = 0, correct = 0;
    bool restarted = false;
    // The scene is only reached inside this call: the processor may replace it at any time.
    const bool running = brailleChosen && trainingMode
                         && processor_.withBrailleTraining([&](braille::BrailleSceneControls& scene, std::uint64_t generation) {
                                if (generation != generation_) {
                                    restarted = generation_ != 0;
                                    generation_ = generation;
                                    feeder_.reset();
                                    complete_ = false;
                                    log_.clear();
                                    tallyCounts_.clear();
                                    heldBack_.clear();
                                    recorder_.reset();   // a new training: a new session in the profile
                                }
                                notices = feeder_.poll(scene);
                                trial = scene.trainingTrial();
                                count = scene.trainingTrialCount();
                                correct = scene.trainingCorrect();
                            });
    if (running != wanted_) {
        wanted_ = running;
        if (onWantedChange) onWantedChange();
        // Shown again (training mode chosen): focus where the reader acts next.
        if (wanted_ && isShowing()) {
            if (complete_) save_.grabKeyboardFocus();
            else answer_.grabKeyboardFocus();
        }
    }
    if (! wanted_) return;
    if (restarted) {
        answer_.setEnabled(true);
        answer_.setTextToShowWhenEmpty(kTypeHere, juce::Colours::grey);
        answerButton_.setEnabled(true);
        for (auto* b : {&repeat_, &skip_, &stop_}) b->setEnabled(true);
        tally_.setText({}, juce::dontSendNotification);
        save_.setVisible(false);
        result_.setText("The braille scene was restarted: the training begins again.", juce::dontSendNotification);
        resized();
    }
    score_.setText(juce::String(correct) + " of " + juce::String(std::min(trial, count)) + " correct", juce::dontSendNotification);
    if (restarted && ! notices.empty()) announce(result_.getText());
    // The next prompt waits until the arm's feedback (and the right cell again) has played.
    if (! heldBack_.empty() && ! processor_.armFeedbackPlaying()) {
        notices.insert(notices.begin(), heldBack_.begin(), heldBack_.end());
        heldBack_.clear();
    }
    show(notices);
}

void TrainingPanel::show(const std::vector<braille::TrainingNotice>& notices)
{
    using Kind = braille::TrainingNotice::Kind;
    juce::String say;
    for (const auto& n : notices) {
        switch (n.kind) {
        case Kind::Result: {
            const bool skipped = n.answer == kSkipAnswer;
            const auto text = skipped ? "skipped (counts as wrong), it was '" + juce::String(n.expected) + "'"
                                      : juce::String(braille::resultText(n)) + (n.right ? juce::String() : ", you answered '" + juce::String(n.answer) + "'");
            result_.setText(text, juce::dontSendNotification);
            // Felt on the arm when that setting is on (deafblind): right / wrong, the right cell again.
            // (A side or "here" has no cell to show again.)
            processor_.armFeedback(n.right, n.stage == "sides" || n.stage == "hold" ? std::string() : n.expected);
            record(n);
            say << text << ". " << n.correct << " of " << n.answered << " correct. ";
            auto it = std::find_if(tallyCounts_.begin(), tallyCounts_.end(), [&](const auto& e) { return e.first == n.expected; });
            if (it == tallyCounts_.end()) it = tallyCounts_.insert(tallyCounts_.end(), {n.expected, {0, 0}});
            it->second.first += n.right ? 1 : 0;
            it->second.second += 1;
            juce::String tally = "Per answer (correct of asked): ";
            for (const auto& e : tallyCounts_)
                tally << juce::String(e.first) << " " << e.second.first << "/" << e.second.second << ",  ";
            tally_.setText(tally.trimCharactersAtEnd(", "), juce::dontSendNotification);
            break;
        }
        case Kind::Prompt:
            if (processor_.armFeedbackPlaying()) {
                heldBack_.push_back(n);
                break;
            }
            promptedAtMs_ = juce::Time::getMillisecondCounterHiRes();
            trial_.setText("Trial " + juce::String(n.trial + 1) + " of " + juce::String(n.trialCount), juce::dontSendNotification);
            // The hold stage is also answered by the arm: a push along the forearm and back.
            prompt_.setText(juce::String(n.prompt) + (n.expected == "here" ? " (type here, or push the forearm along its axis and back)" : ""),
                            juce::dontSendNotification);
            lastPrompt_ = trial_.getText() + ": " + prompt_.getText();
            say << lastPrompt_;
            break;
        case Kind::Complete: {
            complete_ = true;
            const auto text = "Training complete: " + juce::String(n.correct) + " of " + juce::String(n.trialCount) + " correct";
            trial_.setText("All trials answered", juce::dontSendNotification);
            prompt_.setText(text, juce::dontSendNotification);
            say << text << ". " << tally_.getText() << ". Save log to keep it.";
            // The log no longer changes once every trial is answered: keep it now, so a later
            // change of scene or text (which rebuilds the scene) cannot lose it before saving.
            juce::String why;
            if (! processor_.copyBrailleTrainingLog(generation_, log_, why)) log_.clear();
            answer_.setEnabled(false);
            answer_.setTextToShowWhenEmpty("training complete", juce::Colours::grey);
            answerButton_.setEnabled(false);
            for (auto* b : {&repeat_, &skip_}) b->setEnabled(false);
            save_.setVisible(true);
            resized();
            save_.grabKeyboardFocus();
            break;
        }
        }
    }
    announce(say);
}

void TrainingPanel::record(const braille::TrainingNotice& n)
{
    const auto path = processor_.settings()[SettingIds::readerProfile].toString();
    if (path.isEmpty()) return;
    const double nowMs = juce::Time::getMillisecondCounterHiRes();
    try {
        if (! recorder_ || recorderPath_ != path) {
            recorderPath_ = path;
            recorderStartMs_ = nowMs;
            const std::time_t now = std::time(nullptr);
            char date[32];
            std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
            recorder_ = std::make_unique<access::ProfileRecorder>(path.toStdString(), "rows", date);
        }
        recorder_->record(n.stage, n.expected, n.answer, n.right, promptedAtMs_ > 0.0 ? (nowMs - promptedAtMs_) / 1000.0 : -1.0,
                          (nowMs - recorderStartMs_) / 1000.0);
        recorderError_.clear();
    } catch (const std::exception& e) {
        recorder_.reset();
        const auto text = "The reader profile was not updated: " + juce::String(e.what());
        if (text != recorderError_) announce(text);   // said once, not after every answer
        recorderError_ = text;
    }
}

void TrainingPanel::submit()
{
    if (complete_) return;
    answer_.grabKeyboardFocus();   // focus stays in the answer field between trials
    const auto typed = answer_.getText().trim();
    // The trial this answer will be scored for: the current one, after those still on their way.
    juce::String expected;
    processor_.withBrailleTraining([&](braille::BrailleSceneControls& scene, std::uint64_t generation) {
        if (generation != generation_) return;
        const int target = scene.trainingTrial() + (feeder_.awaitingScore() ? 1 : 0) + static_cast<int>(feeder_.waiting());
        if (target >= 0 && target < scene.trainingTrialCount()) expected = juce::String(scene.trainingExpected(target));
    });
    if (const auto why = implausible(typed, expected); why.isNotEmpty()) {
        // A typo is not an answer: it stays in the field to be corrected, nothing is scored.
        const auto text = "Not sent: " + why + " Correct it, then press Return.";
        result_.setText(text, juce::dontSendNotification);
        announce(text);
        answer_.moveCaretToEnd();
        return;
    }
    send(answer_.getText());
}

void TrainingPanel::send(const juce::String& answer)
{
    const auto refusal = feeder_.add(answer.toStdString());
    if (refusal != braille::TrainingAnswerFeeder::Refusal::None) {
        const auto text = "Not sent: " + juce::String(braille::TrainingAnswerFeeder::refusalText(refusal));
        result_.setText(text, juce::dontSendNotification);
        announce(text);
        return;
    }
    answer_.clear();
    follow();   // hand it over now rather than on the next tick
}

juce::String TrainingPanel::implausible(const juce::String& answer, const juce::String& expected)
{
    const auto a = answer.trim().toLowerCase();
    const auto e = expected.toLowerCase();
    if (a.isEmpty() || e.isEmpty()) return {};   // the feeder explains an empty answer
    if (e == "left" || e == "right" || e == "both") {
        if (a != "left" && a != "right" && a != "both") return "'" + answer.trim() + "' is not left, right or both.";
    } else if (e == "here") {
        if (a != "here") return "'" + answer.trim() + "' is not here (answer here when the asked row shows).";
    } else if (e.length() == 1 && juce::CharacterFunctions::isLetter(e[0])) {
        if (a.length() != 1 || ! juce::CharacterFunctions::isLetter(a[0])) return "'" + answer.trim() + "' is not one letter.";
    }
    return {};
}

void TrainingPanel::repeatPrompt()
{
    if (! wanted_) return;
    const auto text = lastPrompt_.isNotEmpty() ? lastPrompt_ : prompt_.getText();
    result_.setText("Prompt again: " + text, juce::dontSendNotification);
    announce(text);
}

void TrainingPanel::skip()
{
    if (! wanted_ || complete_) return;
    answer_.clear();
    send(kSkipAnswer);
    answer_.grabKeyboardFocus();
}

void TrainingPanel::stop()
{
    if (! wanted_) return;
    auto* mode = processor_.parameters().getParameter("braille.mode");
    if (mode == nullptr) return;
    const auto text = "Training stopped: " + score_.getText() + ". The braille scene reads actively again.";
    announce(text);
    mode->setValueNotifyingHost(mode->convertTo0to1(static_cast<float>(braille::BrailleMode::Active)));
    follow();   // hides the panel now
    if (onLeave) onLeave();
}

void TrainingPanel::leave()
{
    announce("Left the training panel; Tab back to it to go on.");
    if (onLeave) onLeave();
}

void TrainingPanel::focusGained(FocusChangeType)
{
    if (complete_ && save_.isShowing()) save_.grabKeyboardFocus();
    else if (answer_.isShowing() && answer_.isEnabled()) answer_.grabKeyboardFocus();
}

bool TrainingPanel::keyPressed(const juce::KeyPress& key)
{
    const bool ctrl = key.getModifiers().isCtrlDown();
    const int code = key.getKeyCode();
    if (code == juce::KeyPress::escapeKey) { leave(); return true; }
    if (code == juce::KeyPress::F5Key || (ctrl && code == 'R')) { repeatPrompt(); return true; }
    if (code == juce::KeyPress::F6Key) { skip(); return true; }
    if (code == juce::KeyPress::F8Key) { stop(); return true; }
    // Nothing else leaves the panel while it trains: arrows do not reach the arm view or a box.
    if (code == juce::KeyPress::upKey || code == juce::KeyPress::downKey || code == juce::KeyPress::leftKey
        || code == juce::KeyPress::rightKey || code == juce::KeyPress::pageUpKey || code == juce::KeyPress::pageDownKey)
        return true;
    return false;
}

void TrainingPanel::save()
{
    auto folder = juce::File::getSpecialLocation(juce::File::userDocumentsDirectory);
    if (! folder.isDirectory()) folder = juce::File::getSpecialLocation(juce::File::userHomeDirectory);
    chooser_ = std::make_unique<juce::FileChooser>("Save training log", folder.getChildFile("braille-training.csv"), "*.csv");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles
                              | juce::FileBrowserComponent::warnAboutOverwriting,
                          [this](const juce::FileChooser& fc) {
                              auto file = fc.getResult();
                              if (file == juce::File()) return;   // dismissed
                              if (! file.hasFileExtension("csv")) file = file.withFileExtension("csv");
                              juce::String message;
                              if (log_.empty() && ! processor_.copyBrailleTrainingLog(generation_, log_, message)) {
                                  log_.clear();
                              } else {
                                  try {
                                      core::writeFileAtomically(file.getFullPathName().toStdString(), log_);
                                      message = "Training log saved to " + file.getFullPathName();
                                  } catch (const std::exception& e) {
                                      message = "The training log was not saved: " + juce::String(e.what());
                                  }
                              }
                              result_.setText(message, juce::dontSendNotification);
                              announce(message);
                              save_.grabKeyboardFocus();
                          });
}

void TrainingPanel::announce(const juce::String& text)
{
    plugin::announce(processor_, "training", text, juce::AccessibilityHandler::AnnouncementPriority::high);
}

void TrainingPanel::paint(juce::Graphics& g) { paintPanel(g, *this); }

void TrainingPanel::resized()
{
    auto r = getLocalBounds().reduced(6, 4);
    // Narrow (the editor's minimum, 200 %): Repeat / Skip / Stop get a row of their own so the
    // answer field stays wide, and the keys get two lines.
    const bool narrow = r.getWidth() < 620;
    const int rows = narrow ? 8 : 7;
    const int row = juce::jmax(18, r.getHeight() / rows);
    const float font = juce::jlimit(12.0f, 20.0f, row * 0.6f);
    heading_.setFont(juce::Font(font, juce::Font::bold));
    trial_.setFont(juce::Font(font));
    score_.setFont(juce::Font(font));
    prompt_.setFont(juce::Font(font + 3.0f, juce::Font::bold));
    result_.setFont(juce::Font(font));
    tally_.setFont(juce::Font(font - 1.0f));
    keys_.setFont(juce::Font(juce::jmax(11.0f, font - 2.0f)));
    answer_.setFont(juce::Font(font + 1.0f));
    answer_.applyFontToAllText(juce::Font(font + 1.0f));

    auto top = r.removeFromTop(row);
    heading_.setBounds(top.removeFromLeft(juce::jmin(170, top.getWidth() / 3)));
    score_.setBounds(top.removeFromRight(top.getWidth() / 2));
    trial_.setBounds(top);
    prompt_.setBounds(r.removeFromTop(row));
    auto line = r.removeFromTop(row).reduced(0, 2);
    const int buttonW = juce::jlimit(64, 120, line.getWidth() / (narrow ? 4 : 8));
    auto actions = narrow ? r.removeFromTop(row).reduced(0, 2) : line;
    for (auto* b : {&stop_, &skip_, &repeat_}) {
        b->setBounds(actions.removeFromRight(buttonW));
        actions.removeFromRight(4);
    }
    if (! narrow) line = line.withRight(actions.getRight());   // the buttons took the line's right end
    if (save_.isVisible()) {
        save_.setBounds(line.removeFromRight(buttonW));
        line.removeFromRight(4);
    }
    answerButton_.setBounds(line.removeFromRight(buttonW));
    line.removeFromRight(6);
    answer_.setBounds(line);
    result_.setBounds(r.removeFromTop(row));
    tally_.setBounds(r.removeFromTop(row));
    keys_.setBounds(r);
}

} // namespace armadillo::plugin
