#include "Plugin/ReaderPanel.h"
#include "Access/ReaderProfile.h"
#include "Access/Report.h"
#include "Link/TouchProfile.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Procedures/AdaptiveTraining.h"

namespace armadillo::plugin {

ReaderPanel::ReaderPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Reader settings");
    setDescription("Self-voicing and braille display, the reader's touch profile, and the progress report.");
    setFocusContainerType(FocusContainerType::focusContainer);
    heading_.setText("Reader: speech, braille display, touch, progress", juce::dontSendNotification);
    heading_.setFont(juce::Font(16.0f, juce::Font::bold));
    describe(heading_, "Reader settings", "Settings for a reader who cannot see or hear the screen.");

    setUpVoice();
    setUpTouch();
    setUpAdaptive();
    setUpAdaptiveChoices();
    setUpReport();
    for (juce::Component* c : std::initializer_list<juce::Component*> {&heading_, &voice_, &rate_, &repeat_, &stop_, &voiceState_, &armFeedback_, &touch_,
                                                                        &loadTouch_, &clearTouch_, &saveTouch_, &startTest_, &felt_, &notFelt_, &again_, &testState_, &adaptiveStart_, &adaptiveAgain_, &adaptiveAnswer_, &adaptiveState_, &adaptiveTrials_, &adaptiveLevel_, &adaptiveMethod_, &adaptiveStages_, &readerProfile_, &forgetReader_, &reportHeading_, &loadReport_, &report_})
        addAndMakeVisible(*c);
    refresh();
    startTimerHz(4);
}

void ReaderPanel::setUpVoice()
{
    voiceLabel_.setText("Speak and braille", juce::dontSendNotification);
    voice_.addItemList({"Auto (when a screen reader or brltty runs)", "On", "Off"}, 1);
    describe(voice_, "Self-voicing",
             "Speak every prompt, answer and message, and write it to the braille display. Auto: on when Orca, "
             "speech-dispatcher or brltty is running.");
    const auto mode = processor_.settings()[SettingIds::readerVoice].toString();
    voice_.setSelectedId(mode == "on" ? 2 : (mode == "off" ? 3 : 1), juce::dontSendNotification);
    voice_.onChange = [this] {
        const int id = voice_.getSelectedId();
        processor_.settings().setProperty(SettingIds::readerVoice, id == 2 ? "on" : (id == 3 ? "off" : "auto"), nullptr);
        refresh();
    };
    voiceLabel_.attachToComponent(&voice_, true);

    rateLabel_.setText("Speech rate", juce::dontSendNotification);
    rate_.setRange(-100.0, 100.0, 10.0);
    rate_.setSliderStyle(juce::Slider::LinearHorizontal);
    rate_.setTextBoxStyle(juce::Slider::TextBoxRight, false, 50, 20);
    describe(rate_, "Speech rate", "From -100 (slowest) through 0 (the voice's own) to +100 (fastest). Arrow keys change it.");
    rate_.setValue(static_cast<int>(processor_.settings()[SettingIds::speechRate]), juce::dontSendNotification);
    rate_.onDragEnd = [this] { announce("Speech rate " + juce::String(static_cast<int>(rate_.getValue()))); };
    rate_.onValueChange = [this] {
        processor_.settings().setProperty(SettingIds::speechRate, static_cast<int>(rate_.getValue()), nullptr);
        if (! rate_.isMouseButtonDown()) announce("Speech rate " + juce::String(static_cast<int>(rate_.getValue())));
    };
    rateLabel_.attachToComponent(&rate_, true);
    describe(repeat_, "Repeat", "Say the last prompt or message again (F3 in the training answer field).");
    repeat_.onClick = [this] { processor_.voice().repeat(); };
    describe(stop_, "Stop speech", "Stop speaking now (F4 in the training answer field).");
    stop_.onClick = [this] { processor_.voice().stop(); };
    describe(armFeedback_, "Feedback on the arm",
             "After each training answer the arm says right (all nine motors hum softly) or wrong (the outer columns buzz "
             "three times), so a reader who cannot see or hear the screen trains alone.");
    armFeedback_.getToggleStateValue().referTo(processor_.settings().getPropertyAsValue(SettingIds::armFeedback, nullptr));
    armFeedback_.onClick = [this] { announce(armFeedback_.getToggleState() ? "Feedback on the arm: on" : "Feedback on the arm: off"); };
    describe(voiceState_, "Speech and display state", "Which voice and braille display are in use.");
}

void ReaderPanel::setUpTouch()
{
    describe(touch_, "Touch profile", "The reader's touch profile: each motor's threshold, used to scale it.");
    describe(loadTouch_, "Load touch profile",
             "Load a touch profile made by armadillo touch-profile. It is saved with the setup and scales every motor.");
    loadTouch_.onClick = [this] { choose(true); };
    describe(clearTouch_, "No touch profile", "Drive every motor alike again.");
    clearTouch_.onClick = [this] {
        processor_.settings().setProperty(SettingIds::touchProfile, "", nullptr);
        refresh();
    };

    describe(startTest_, "Sensitivity test",
             "Measure how strongly you feel each of the nine motors: one motor buzzes at a time; answer felt (Y) or "
             "not felt (N). Then a comfortable level on motor m5: Y when clear and comfortable, N while too faint. "
             "About 5 minutes. The result becomes your touch profile. Press again to stop.");
    startTest_.onClick = [this] { startTest(); };
    describe(felt_, "Felt", "You felt the last buzz (key Y).");
    felt_.onClick = [this] { answerTest(true); };
    describe(notFelt_, "Not felt", "You did not feel the last buzz (key N).");
    notFelt_.onClick = [this] { answerTest(false); };
    describe(again_, "Again", "Play the last buzz again (key R).");
    again_.onClick = [this] {
        processor_.touchTest().again();
        followTest();
    };
    describe(testState_, "Sensitivity test state", "Which motor and level the test is at, or its result.");
    describe(saveTouch_, "Save touch profile", "Write the touch profile in use to a file (for armadillo --profile).");
    saveTouch_.onClick = [this] { saveProfile(); };
}

void ReaderPanel::setUpAdaptive()
{
    describe(adaptiveStart_, "Adaptive training",
             "Train letters and words adapted to everything you answered before: choose or name your reader profile "
             "file. The trials, stages, method and level below; drawn on the arm; answer in the field (letters and Return, "
             "or F2 and chords then Space), or twist the forearm and back to feel it again, twice to skip. Press again to stop.");
    adaptiveStart_.onClick = [this] { startAdaptive(); };
    describe(adaptiveAgain_, "Show again", "Draw the current trial on the arm again.");
    adaptiveAgain_.onClick = [this] {
        processor_.adaptive().again();
        adaptiveAnswer_.grabKeyboardFocus();
    };
    describe(adaptiveAnswer_, "Adaptive answer", "Your answer to the adaptive trial; Return sends it. F2: chords.");
    adaptiveAnswer_.setTextToShowWhenEmpty("answer here, then Return", juce::Colours::grey);
    adaptiveAnswer_.setInputRestrictions(64);
    adaptiveAnswer_.onReturnKey = [this] { answerAdaptive(); };
    adaptiveKeys_.attach(adaptiveAnswer_, [this] { answerAdaptive(); }, [this](const juce::String& t) { announce(t); },
                         &processor_.voice());
    describe(adaptiveState_, "Adaptive training state", "The trial and its prompt, or the last feedback.");
}

void ReaderPanel::setUpAdaptiveChoices()
{
    // The adaptive training's choices, kept in the settings (the CLI's --trials --stages --method --level).
    auto& settings = processor_.settings();
    trialsLabel_.setText("Trials", juce::dontSendNotification);
    adaptiveTrials_.setRange(1.0, 500.0, 1.0);
    adaptiveTrials_.setSliderStyle(juce::Slider::IncDecButtons);
    adaptiveTrials_.setTextBoxStyle(juce::Slider::TextBoxLeft, false, 50, 20);
    describe(adaptiveTrials_, "Trials", "How many trials the adaptive training gives (1 to 500; arrow keys change it).");
    adaptiveTrials_.setValue(static_cast<int>(settings[SettingIds::adaptiveTrials]), juce::dontSendNotification);
    adaptiveTrials_.onValueChange = [this] {
        processor_.settings().setProperty(SettingIds::adaptiveTrials, static_cast<int>(adaptiveTrials_.getValue()), nullptr);
        announce("Trials " + juce::String(static_cast<int>(adaptiveTrials_.getValue())));
    };
    trialsLabel_.attachToComponent(&adaptiveTrials_, true);
    levelLabel_.setText("Level", juce::dontSendNotification);
    adaptiveLevel_.setRange(1.0, 15.0, 1.0);
    adaptiveLevel_.setSliderStyle(juce::Slider::IncDecButtons);
    adaptiveLevel_.setTextBoxStyle(juce::Slider::TextBoxLeft, false, 40, 20);
    describe(adaptiveLevel_, "Level", "How strongly the cells are drawn, 1 to 15 (arrow keys change it).");
    adaptiveLevel_.setValue(static_cast<int>(settings[SettingIds::adaptiveLevel]), juce::dontSendNotification);
    adaptiveLevel_.onValueChange = [this] {
        processor_.settings().setProperty(SettingIds::adaptiveLevel, static_cast<int>(adaptiveLevel_.getValue()), nullptr);
        announce("Level " + juce::String(static_cast<int>(adaptiveLevel_.getValue())));
    };
    levelLabel_.attachToComponent(&adaptiveLevel_, true);
    methodLabel_.setText("Method", juce::dontSendNotification);
    adaptiveMethod_.addItemList({"rows", "whole", "columns", "dots"}, 1);
    describe(adaptiveMethod_, "Method", "How a cell is drawn: rows (the thesis), whole, columns, or dots (one dot at a time).");
    adaptiveMethod_.setText(settings[SettingIds::adaptiveMethod].toString(), juce::dontSendNotification);
    adaptiveMethod_.onChange = [this] {
        processor_.settings().setProperty(SettingIds::adaptiveMethod, adaptiveMethod_.getText(), nullptr);
        announce("Method " + adaptiveMethod_.getText());
    };
    methodLabel_.attachToComponent(&adaptiveMethod_, true);
    stagesLabel_.setText("Stages", juce::dontSendNotification);
    describe(adaptiveStages_, "Stages",
             "What the adaptive training trains, in order, separated by commas: letters, words, signs, contractions. Return keeps it.");
    adaptiveStages_.setText(settings[SettingIds::adaptiveStages].toString(), false);
    adaptiveStages_.onReturnKey = [this] { takeStages(); };
    adaptiveStages_.onFocusLost = [this] { takeStages(); };
    stagesLabel_.attachToComponent(&adaptiveStages_, true);
    describe(readerProfile_, "Reader profile", "The reader profile in use: the adaptive training and the Training panel add every answer to it.");
    describe(forgetReader_, "No reader profile", "Stop adding the Training panel's answers to a reader profile.");
    forgetReader_.onClick = [this] {
        processor_.settings().setProperty(SettingIds::readerProfile, "", nullptr);
        showReaderProfile();
    };
}

void ReaderPanel::setUpReport()
{
    reportHeading_.setText("Progress", juce::dontSendNotification);
    describe(reportHeading_, "Progress", "The progress report of a reader profile.");
    describe(loadReport_, "Progress report",
             "Open a reader profile (the file armadillo braille --adaptive keeps) and show its progress report.");
    loadReport_.onClick = [this] { choose(false); };
    describe(report_, "Progress report text",
             "Accuracy per stage and session, letters per minute, the confusion matrix and the published figures. "
             "Read it line by line with the arrow keys.");
    messagesHeading_.setText("Messages", juce::dontSendNotification);
    messagesHeading_.setFont(juce::Font(15.0f, juce::Font::bold));
    addAndMakeVisible(messagesHeading_);
    messages_.setTitle("Messages");
    messages_.setDescription("The messages received over MQTT (Setup, MQTT messages), newest last: each with where it came from and "
                             "whether it was shown on the arm. Read it line by line with the arrow keys.");
    messages_.setWantsKeyboardFocus(true);
    messages_.setMultiLine(true, false);
    messages_.setReadOnly(true);
    messages_.setCaretVisible(true);
    messages_.setTextToShowWhenEmpty("no messages (Setup, MQTT messages... connects to a broker)", juce::Colours::grey);
    addAndMakeVisible(messages_);
    report_.setMultiLine(true, false);
    report_.setReadOnly(true);
    report_.setCaretVisible(true);   // the caret is where a braille reader reads
    report_.setFont(juce::Font(juce::Font::getDefaultMonospacedFontName(), 14.0f, juce::Font::plain));
    report_.setTextToShowWhenEmpty("no report loaded", juce::Colours::grey);
}

ReaderPanel::~ReaderPanel()
{
    stopTimer();
    adaptiveStages_.onFocusLost = nullptr;   // no announcement from a field being destroyed
    adaptiveAnswer_.removeKeyListener(&adaptiveKeys_);
    if (processor_.adaptive().state() != procedures::AdaptiveTraining::State::Idle) processor_.endAdaptive();
    if (processor_.touchTest().state() != procedures::TouchTest::State::Idle) processor_.endTouchTest(false);   // the motors back to the scene
}

void ReaderPanel::timerCallback()
{
    followTest();
    followAdaptive();
    refresh();
    showReaderProfile();
    followMessages();
}

void ReaderPanel::followMessages()
{
    const auto* service = processor_.messages().service();
    juce::String text;
    if (service != nullptr) {
        text << "MQTT: " << juce::String(service->describe()) << "\n";
        for (const auto& m : service->recent(20)) {
            text << juce::String(m.id) << ". " << juce::String::fromUTF8(m.text.c_str()) << "  (from " << juce::String(m.source)
                 << (m.urgent ? ", urgent" : "") << ")\n";
            if (m.id > lastMessageId_) {   // a new one: said once
                lastMessageId_ = m.id;
                announce("Message from " + juce::String(m.source) + ": " + juce::String::fromUTF8(m.text.c_str()));
            }
        }
    } else {
        text << "MQTT: stopped";
    }
    for (const auto& line : processor_.messageLog()) text << "\n" << line;
    if (text != messages_.getText()) {
        const auto caret = messages_.getCaretPosition();
        messages_.setText(text, false);
        messages_.setCaretPosition(caret);
    }
}

void ReaderPanel::showReaderProfile()
{
    const auto path = processor_.settings()[SettingIds::readerProfile].toString();
    if (path == shownReader_) return;
    const bool first = shownReader_ == "?";
    shownReader_ = path;
    readerProfile_.setText(path.isEmpty() ? juce::String("Reader profile: none (the Training panel keeps no answers)")
                                          : "Reader profile: " + path + " (the Training panel adds its answers too)",
                           juce::dontSendNotification);
    forgetReader_.setEnabled(path.isNotEmpty());
    if (! first) announce(readerProfile_.getText());
}

juce::String ReaderPanel::takeStages()
{
    procedures::AdaptiveChoices c;
    c.stages = adaptiveStages_.getText().removeCharacters(" ").toLowerCase().toStdString();
    if (const auto why = c.problem(); ! why.empty()) {
        const auto text = "Stages not changed: " + juce::String(why);
        announce(text);
        adaptiveStages_.setText(processor_.settings()[SettingIds::adaptiveStages].toString(), false);
        return text;
    }
    if (juce::String(c.stages) != processor_.settings()[SettingIds::adaptiveStages].toString()) {
        processor_.settings().setProperty(SettingIds::adaptiveStages, juce::String(c.stages), nullptr);
        announce("Stages " + juce::String(c.stages));
    }
    adaptiveStages_.setText(juce::String(c.stages), false);
    return {};
}

void ReaderPanel::startAdaptive()
{
    if (processor_.adaptive().state() == procedures::AdaptiveTraining::State::Drawing || processor_.adaptive().state() == procedures::AdaptiveTraining::State::Answering) {
        processor_.endAdaptive();
        adaptiveState_.setText("Adaptive training stopped; the reader profile keeps every answer.", juce::dontSendNotification);
        announce(adaptiveState_.getText());
        followAdaptive();
        return;
    }
    auto start = juce::File::getSpecialLocation(juce::File::userDocumentsDirectory).getChildFile("reader.json");
    if (const auto saved = processor_.settings()[SettingIds::readerProfile].toString(); juce::File::isAbsolutePath(saved)) start = juce::File(saved);
    if (readerFile_ != juce::File()) start = readerFile_;
    chooser_ = std::make_unique<juce::FileChooser>("Your reader profile (a new name starts a new one)", start, "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles, [this](const juce::FileChooser& fc) {
        auto file = fc.getResult();
        if (file == juce::File()) return;
        if (! file.hasFileExtension("json")) file = file.withFileExtension("json");
        juce::String why;
        if (! processor_.beginAdaptive(file, why)) {
            adaptiveState_.setText("Adaptive training cannot start: " + why, juce::dontSendNotification);
            announce(adaptiveState_.getText());
            return;
        }
        readerFile_ = file;
        const auto c = processor_.adaptiveChoices();
        announce("Adaptive training, " + juce::String(c.trials) + " trials of " + juce::String(c.stages) + ", method " + juce::String(c.method)
                 + ", level " + juce::String(c.level) + ", with " + file.getFileName()
                 + ". Feel the arm, then answer. A twist of the forearm and back shows it again; two twists skip. The session log goes to "
                 + juce::File(processor_.adaptive().logPath()).getFileName() + ".");
        followAdaptive();                      // enables the answer field first: a disabled one takes no focus
        adaptiveAnswer_.grabKeyboardFocus();
    });
}

void ReaderPanel::answerAdaptive()
{
    auto& session = processor_.adaptive();
    if (session.state() != procedures::AdaptiveTraining::State::Answering) {
        announce(session.state() == procedures::AdaptiveTraining::State::Drawing ? "Wait: the trial is still being drawn." : "No adaptive training is running.");
        return;
    }
    const auto rt = (juce::Time::getMillisecondCounterHiRes() - promptedAt_) / 1000.0;
    const auto feedback = juce::String(session.answer(adaptiveAnswer_.getText().toStdString(), rt));
    adaptiveAnswer_.clear();
    adaptiveState_.setText(feedback, juce::dontSendNotification);
    announce(feedback);
    if (session.state() == procedures::AdaptiveTraining::State::Done) {
        processor_.endAdaptive();
        if (readerFile_.existsAsFile()) showReport(readerFile_);   // where the reader stands now
    }
    followAdaptive();
}

void ReaderPanel::followAdaptive()
{
    auto& session = processor_.adaptive();
    // The arm's twists (read by the control step while the training has the motors).
    switch (session.takeGesture()) {
    case procedures::AdaptiveTraining::Gesture::Repeat:
        session.again();
        announce("Again (a twist of the arm).");
        break;
    case procedures::AdaptiveTraining::Gesture::Skip: {
        const auto rt = (juce::Time::getMillisecondCounterHiRes() - promptedAt_) / 1000.0;
        const auto feedback = "Skipped by the arm: " + juce::String(session.skip(rt));
        adaptiveState_.setText(feedback, juce::dontSendNotification);
        announce(feedback);
        if (session.state() == procedures::AdaptiveTraining::State::Done) {
            processor_.endAdaptive();
            if (readerFile_.existsAsFile()) showReport(readerFile_);
        }
        break;
    }
    case procedures::AdaptiveTraining::Gesture::None: break;
    }
    if (session.poll()) {
        promptedAt_ = juce::Time::getMillisecondCounterHiRes();
        adaptiveState_.setText(juce::String(session.prompt()), juce::dontSendNotification);
        announce(adaptiveState_.getText());
        adaptiveAnswer_.setEnabled(true);
        if (isShowing()) adaptiveAnswer_.grabKeyboardFocus();   // where the reader answers, whatever had focus
    }
    const bool running = session.state() == procedures::AdaptiveTraining::State::Drawing || session.state() == procedures::AdaptiveTraining::State::Answering;
    adaptiveStart_.setButtonText(running ? "Stop training" : "Adaptive training...");
    adaptiveAgain_.setEnabled(session.state() == procedures::AdaptiveTraining::State::Answering);
    adaptiveAnswer_.setEnabled(running);
}

void ReaderPanel::startTest()
{
    auto& test = processor_.touchTest();
    if (test.state() == procedures::TouchTest::State::Presenting || test.state() == procedures::TouchTest::State::Asking) {
        processor_.endTouchTest(false);
        testState_.setText("Sensitivity test stopped; nothing kept.", juce::dontSendNotification);
        announce(testState_.getText());
        followTest();
        return;
    }
    processor_.beginTouchTest(static_cast<std::uint64_t>(juce::Time::currentTimeMillis()));
    comfortAnnounced_ = false;
    announce("Sensitivity test: one motor buzzes at a time. After each, press Y if you felt it, N if not, R to feel it again.");
    felt_.grabKeyboardFocus();
    followTest();
}

void ReaderPanel::answerTest(bool felt)
{
    processor_.touchTest().answer(felt);
    followTest();
}

void ReaderPanel::followTest()
{
    auto& test = processor_.touchTest();
    using State = procedures::TouchTest::State;
    const bool wasComfort = comfortAnnounced_;
    if (test.comfortStep() && ! wasComfort) {
        comfortAnnounced_ = true;
        announce("Thresholds measured. Now a comfortable level on motor m5: press Y when it is clear and comfortable, N while it is too faint.");
    }
    if (test.poll()) {   // a stimulus was just played: ask
        testState_.setText("Stimulus " + juce::String(test.stimuli()) + ": " + juce::String(test.question()), juce::dontSendNotification);
        announce(testState_.getText());
    } else if (test.state() == State::Presenting) {
        testState_.setText("Stimulus " + juce::String(test.stimuli()) + ": feel...", juce::dontSendNotification);
    } else if (test.state() == State::Done) {
        processor_.endTouchTest(true);   // the profile becomes the setting; refresh() announces the thresholds
        testState_.setText("Sensitivity test complete: the profile is in use.", juce::dontSendNotification);
        announce(testState_.getText());
    }
    const bool asking = test.state() == State::Asking;
    felt_.setEnabled(asking);
    notFelt_.setEnabled(asking);
    again_.setEnabled(asking);
    const bool running = asking || test.state() == State::Presenting;
    startTest_.setButtonText(running ? "Stop the test" : "Sensitivity test");
}

bool ReaderPanel::keyPressed(const juce::KeyPress& key)
{
    const auto c = juce::CharacterFunctions::toLowerCase(key.getTextCharacter());
    if (processor_.touchTest().state() == procedures::TouchTest::State::Asking && (c == 'y' || c == 'n' || c == 'r')) {
        if (c == 'r') processor_.touchTest().again();
        else answerTest(c == 'y');
        followTest();
        return true;
    }
    if (key.getKeyCode() == juce::KeyPress::F3Key) {
        processor_.voice().repeat();
        return true;
    }
    if (key.getKeyCode() == juce::KeyPress::F4Key) {
        processor_.voice().stop();
        return true;
    }
    return false;
}

void ReaderPanel::saveProfile()
{
    const auto json = processor_.settings()[SettingIds::touchProfile].toString();
    if (json.isEmpty()) {
        announce("No touch profile in use: load one or run the sensitivity test first.");
        return;
    }
    chooser_ = std::make_unique<juce::FileChooser>("Save the touch profile",
                                                   juce::File::getSpecialLocation(juce::File::userDocumentsDirectory).getChildFile("touch-profile.json"),
                                                   "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles
                              | juce::FileBrowserComponent::warnAboutOverwriting,
                          [this, json](const juce::FileChooser& fc) {
                              const auto file = fc.getResult();
                              if (file == juce::File()) return;
                              try {
                                  link::saveTouchProfile(file.getFullPathName().toStdString(),
                                                           link::parseTouchProfile(json.toStdString(), "the touch profile setting"));
                                  announce("Touch profile saved to " + file.getFullPathName());
                              } catch (const std::exception& e) {
                                  announce("The touch profile was not saved: " + juce::String(e.what()));
                              }
                          });
}

void ReaderPanel::refresh()
{
    const auto json = processor_.settings()[SettingIds::touchProfile].toString();
    if (json != shownTouch_) {
        const bool first = shownTouch_ == "?";
        shownTouch_ = json;
        juce::String text = "Touch profile: none (every motor alike)";
        if (json.isNotEmpty()) {
            try {
                const auto profile = link::parseTouchProfile(json.toStdString(), "the touch profile setting");
                text = "Touch profile: thresholds";
                for (int m = 0; m < link::kProfileMotors; ++m)
                    text << " m" << (m + 1) << "=" << profile.threshold[static_cast<std::size_t>(m)];
                if (profile.comfort > 0) text << "; comfortable level " << profile.comfort << " (m" << profile.comfortMotor << ")";
            } catch (const std::exception& e) {
                text = "Touch profile not used: " + juce::String(e.what());
            }
        }
        touch_.setText(text, juce::dontSendNotification);
        if (! first) announce(text);
    }
    const juce::String state = processor_.voiceOn()
                                   ? juce::String("On: ") + (processor_.voice().speaking() ? "speech" : "no speech") + ", "
                                         + (processor_.voice().showing() ? "braille display" : "no braille display")
                                   : juce::String("Off");
    if (state != shownVoice_) {
        const bool first = shownVoice_.isEmpty();
        shownVoice_ = state;
        voiceState_.setText("Self-voicing: " + state, juce::dontSendNotification);
        if (! first) announce(voiceState_.getText());
    }
}

juce::String ReaderPanel::loadTouchProfile(const juce::File& file)
{
    juce::String message;
    try {
        const auto profile = link::loadTouchProfile(file.getFullPathName().toStdString());
        processor_.settings().setProperty(SettingIds::touchProfile, juce::String(link::touchProfileToJson(profile)), nullptr);
        refresh();   // announces the thresholds
        return {};
    } catch (const std::exception& e) {
        message = "The touch profile was not loaded: " + juce::String(e.what());
    }
    announce(message);
    return message;
}

juce::String ReaderPanel::showReport(const juce::File& file)
{
    try {
        const auto path = file.getFullPathName().toStdString();
        if (! file.existsAsFile()) throw std::runtime_error(path + ": no such file");
        const auto text = juce::String(access::progressReport(access::parseReaderProfile(file.loadFileAsString().toStdString(), path)));
        report_.setText(text, false);
        report_.moveCaretToTop(false);
        report_.grabKeyboardFocus();
        announce("Progress report of " + file.getFileName() + ". " + text.upToFirstOccurrenceOf("\n", false, false));
        return {};
    } catch (const std::exception& e) {
        const auto message = "The progress report cannot be made: " + juce::String(e.what());
        report_.setText(message, false);
        announce(message);
        return message;
    }
}

void ReaderPanel::choose(bool profile)
{
    auto folder = juce::File::getSpecialLocation(juce::File::userDocumentsDirectory);
    chooser_ = std::make_unique<juce::FileChooser>(profile ? "Load a touch profile" : "Open a reader profile", folder, "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles,
                          [this, profile](const juce::FileChooser& fc) {
                              const auto file = fc.getResult();
                              if (file == juce::File()) return;
                              if (profile) loadTouchProfile(file);
                              else showReport(file);
                          });
}

void ReaderPanel::announce(const juce::String& text)
{
    plugin::announce(processor_, "reader", text, juce::AccessibilityHandler::AnnouncementPriority::high);
}

void ReaderPanel::paint(juce::Graphics& g) { paintPanel(g, *this); }

void ReaderPanel::resized()
{
    auto r = getLocalBounds().reduced(8);
    const int row = 28;
    heading_.setBounds(r.removeFromTop(row));
    auto line = r.removeFromTop(row).reduced(0, 2);
    line.removeFromLeft(130);
    voice_.setBounds(line.removeFromLeft(juce::jmin(320, line.getWidth())));
    r.removeFromTop(4);
    line = r.removeFromTop(row).reduced(0, 2);
    line.removeFromLeft(130);
    rate_.setBounds(line.removeFromLeft(juce::jmin(320, line.getWidth())));
    r.removeFromTop(4);
    line = r.removeFromTop(row).reduced(0, 2);
    repeat_.setBounds(line.removeFromLeft(120));
    line.removeFromLeft(6);
    stop_.setBounds(line.removeFromLeft(140));
    line.removeFromLeft(10);
    voiceState_.setBounds(line);
    r.removeFromTop(4);
    armFeedback_.setBounds(r.removeFromTop(row));
    r.removeFromTop(8);
    touch_.setBounds(r.removeFromTop(row));
    line = r.removeFromTop(row).reduced(0, 2);
    loadTouch_.setBounds(line.removeFromLeft(170));
    line.removeFromLeft(6);
    clearTouch_.setBounds(line.removeFromLeft(140));
    line.removeFromLeft(6);
    saveTouch_.setBounds(line.removeFromLeft(170));
    r.removeFromTop(4);
    line = r.removeFromTop(row).reduced(0, 2);
    startTest_.setBounds(line.removeFromLeft(140));
    line.removeFromLeft(6);
    felt_.setBounds(line.removeFromLeft(90));
    line.removeFromLeft(6);
    notFelt_.setBounds(line.removeFromLeft(110));
    line.removeFromLeft(6);
    again_.setBounds(line.removeFromLeft(90));
    testState_.setBounds(r.removeFromTop(row));
    r.removeFromTop(4);
    line = r.removeFromTop(row).reduced(0, 2);
    adaptiveStart_.setBounds(line.removeFromLeft(160));
    line.removeFromLeft(6);
    adaptiveAgain_.setBounds(line.removeFromLeft(100));
    line.removeFromLeft(6);
    adaptiveAnswer_.setBounds(line);
    adaptiveState_.setBounds(r.removeFromTop(row));
    line = r.removeFromTop(row).reduced(0, 2);
    line.removeFromLeft(50);
    adaptiveTrials_.setBounds(line.removeFromLeft(120));
    line.removeFromLeft(60);
    adaptiveLevel_.setBounds(line.removeFromLeft(100));
    line.removeFromLeft(60);
    adaptiveMethod_.setBounds(line.removeFromLeft(100));
    line.removeFromLeft(60);
    adaptiveStages_.setBounds(line);
    line = r.removeFromTop(row).reduced(0, 2);
    forgetReader_.setBounds(line.removeFromRight(140));
    readerProfile_.setBounds(line);
    r.removeFromTop(8);
    messagesHeading_.setBounds(r.removeFromTop(row));
    messages_.setBounds(r.removeFromTop(juce::jmax(60, r.getHeight() / 3)));
    r.removeFromTop(4);
    line = r.removeFromTop(row).reduced(0, 2);
    reportHeading_.setBounds(line.removeFromLeft(100));
    loadReport_.setBounds(line.removeFromLeft(170));
    r.removeFromTop(4);
    report_.setBounds(r);
}

} // namespace armadillo::plugin
