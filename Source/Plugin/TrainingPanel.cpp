#include "Plugin/TrainingPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Core/AtomicFile.h"
#include <algorithm>
#include <cmath>
#include <iostream>

namespace armadillo::plugin {

namespace {
constexpr int kMaxTypedCharacters = 1024;   // a pasted book stops here; the feeder refuses > 63 bytes anyway
const char* const kTypeHere = "type the answer, then Return";
const char* const kHint = "Feel what the arm shows, type the answer, press Return.";
} // namespace

TrainingPanel::TrainingPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    mode_ = processor_.parameters().getRawParameterValue("braille.mode");
    setTitle("Braille training");
    setDescription("The braille training of thesis section 4.4.1: feel what the arm shows, type the answer, press Return.");
    setFocusContainerType(FocusContainerType::focusContainer);

    heading_.setText("Braille training", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    describe(heading_, "Braille training", "The braille scene's training mode: one trial after another.");
    // A label's accessible name is its text: a screen reader reads the trial, prompt and result.
    describe(trial_, "Training trial", "Which trial this is, of how many.");
    describe(prompt_, "Training prompt", "What to feel for and answer in this trial.");
    describe(score_, "Training score", "How many answers were right so far.");
    describe(result_, "Training result", "Whether the last answer was right, or why it was not sent.");
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
    keys_.attach(answer_, [this] { submit(); }, [this](const juce::String& t) { announce(t); }, &processor_.voice());
    describe(answerButton_, "Answer", "Send the answer in the field (the same as Return).");
    answerButton_.onClick = [this] { submit(); };
    describe(save_, "Save training log", "Write the training log (CSV, one row per event) to a file.");
    save_.onClick = [this] { save(); };

    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &trial_, &score_, &prompt_, &answer_,
                                                                        &answerButton_, &result_})
        addAndMakeVisible(*c);
    addChildComponent(save_);
    result_.setText(kHint, juce::dontSendNotification);
    startTimerHz(20);
}

TrainingPanel::~TrainingPanel()
{
    stopTimer();
    answer_.removeKeyListener(&keys_);
}

void TrainingPanel::timerCallback()
{
    if (wanted_ && ! complete_) keys_.pollDisplay();
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
        save_.setVisible(false);
        result_.setText("The braille scene was restarted: the training begins again.", juce::dontSendNotification);
        resized();
    }
    score_.setText(juce::String(correct) + " of " + juce::String(std::min(trial, count)) + " right", juce::dontSendNotification);
    if (restarted && ! notices.empty()) announce(result_.getText());
    show(notices);
}

void TrainingPanel::show(const std::vector<braille::TrainingNotice>& notices)
{
    using Kind = braille::TrainingNotice::Kind;
    juce::String say;
    for (const auto& n : notices) {
        switch (n.kind) {
        case Kind::Result: {
            const auto text = juce::String(braille::resultText(n));
            result_.setText(text, juce::dontSendNotification);
            processor_.armFeedback(n.right);   // felt on the arm when that setting is on (deafblind)
            say << text << ". " << n.correct << " of " << n.answered << " right. ";
            break;
        }
        case Kind::Prompt:
            trial_.setText("Trial " + juce::String(n.trial + 1) + " of " + juce::String(n.trialCount), juce::dontSendNotification);
            prompt_.setText(juce::String(n.prompt), juce::dontSendNotification);
            say << trial_.getText() << ": " << prompt_.getText();
            break;
        case Kind::Complete: {
            complete_ = true;
            const auto text = "Training complete: " + juce::String(n.correct) + " of " + juce::String(n.trialCount) + " right";
            trial_.setText("All trials answered", juce::dontSendNotification);
            prompt_.setText(text, juce::dontSendNotification);
            say << text << ". Save log to keep it.";
            // The log no longer changes once every trial is answered: keep it now, so a later
            // change of scene or text (which rebuilds the scene) cannot lose it before saving.
            juce::String why;
            if (! processor_.copyBrailleTrainingLog(generation_, log_, why)) log_.clear();
            answer_.setEnabled(false);
            answer_.setTextToShowWhenEmpty("training complete", juce::Colours::grey);
            answerButton_.setEnabled(false);
            save_.setVisible(true);
            resized();
            save_.grabKeyboardFocus();
            break;
        }
        }
    }
    announce(say);
}

void TrainingPanel::submit()
{
    if (complete_) return;
    const auto refusal = feeder_.add(answer_.getText().toStdString());
    answer_.grabKeyboardFocus();   // focus stays in the answer field between trials
    if (refusal != braille::TrainingAnswerFeeder::Refusal::None) {
        const auto text = "Not sent: " + juce::String(braille::TrainingAnswerFeeder::refusalText(refusal));
        result_.setText(text, juce::dontSendNotification);
        announce(text);
        return;
    }
    answer_.clear();
    follow();   // hand it over now rather than on the next tick
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
                                      writeFileAtomically(file.getFullPathName().toStdString(), log_);
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
    const int row = juce::jmax(18, r.getHeight() / 4);
    const float font = juce::jlimit(13.0f, 20.0f, row * 0.6f);
    heading_.setFont(juce::Font(font, juce::Font::bold));
    trial_.setFont(juce::Font(font));
    score_.setFont(juce::Font(font));
    prompt_.setFont(juce::Font(font + 3.0f, juce::Font::bold));
    result_.setFont(juce::Font(font));
    answer_.setFont(juce::Font(font + 1.0f));
    answer_.applyFontToAllText(juce::Font(font + 1.0f));

    auto top = r.removeFromTop(row);
    heading_.setBounds(top.removeFromLeft(juce::jmin(170, top.getWidth() / 3)));
    score_.setBounds(top.removeFromRight(top.getWidth() / 2));
    trial_.setBounds(top);
    prompt_.setBounds(r.removeFromTop(row));
    auto line = r.removeFromTop(row).reduced(0, 2);
    const int buttonW = juce::jlimit(80, 130, line.getWidth() / 5);
    if (save_.isVisible()) {
        save_.setBounds(line.removeFromRight(buttonW));
        line.removeFromRight(6);
    }
    answerButton_.setBounds(line.removeFromRight(buttonW));
    line.removeFromRight(6);
    answer_.setBounds(line);
    result_.setBounds(r);
}

} // namespace armadillo::plugin
