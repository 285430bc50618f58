#include "Plugin/PluginEditor.h"
#include "Plugin/MappingPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/FactoryPresets.h"
#include "Plugin/PluginProcessor.h"
#include "Plugin/StandaloneAccess.h"
#include "Plugin/ReaderPanel.h"
#include "Plugin/TactorsPanel.h"
#include "Plugin/NavigationPanel.h"
#include "Plugin/MqttPanel.h"
#include "Plugin/WebPanel.h"
#include "Core/Resources.h"
#include "Core/Version.h"

namespace armadillo::plugin {

namespace {
/// Where the setup dialogs start: the Documents folder when it exists, else the home folder
/// (a fresh account or a minimal desktop often has no "Documents").
juce::File setupFolder()
{
    const auto documents = juce::File::getSpecialLocation(juce::File::userDocumentsDirectory);
    return documents.isDirectory() ? documents : juce::File::getSpecialLocation(juce::File::userHomeDirectory);
}
} // namespace

ArmadilloEditor::ArmadilloEditor(ArmadilloProcessor& processor)
    : AudioProcessorEditor(processor), processor_(processor), armView_(processor), motors_(processor),
      device_(processor), sceneControls_(processor), training_(processor), welcome_(processor),
      performance_(processor)
{
    setTitle("ARMadillo");
    setDescription("Forearm controller and tactile display. F1 opens the help.");
    // Standalone only (a plugin must not rescale its host): ARMADILLO_UI_SCALE=2 for 200 % on a
    // Linux desktop that does not announce its scale to JUCE.
    if (processor_.wrapperType == juce::AudioProcessor::wrapperType_Standalone) {
        const auto scale = juce::SystemStats::getEnvironmentVariable("ARMADILLO_UI_SCALE", {}).getFloatValue();
        if (scale >= 0.5f && scale <= 4.0f) juce::Desktop::getInstance().setGlobalScaleFactor(scale);
    }
    title_.setText("ARMadillo", juce::dontSendNotification);
    title_.setFont(juce::Font(22.0f, juce::Font::bold));
    addAndMakeVisible(title_);

    sourceLabel_.setText("Source", juce::dontSendNotification);
    sceneLabel_.setText("Scene", juce::dontSendNotification);
    presetLabel_.setText("Preset", juce::dontSendNotification);
    source_.addItemList(sourceChoiceNames(), 1);
    describe(source_, "Source", "Where the arm's orientation comes from: device, simulator, OSC or host automation. "
                                "Arrows or Return open the list.");
    sourceAttachment_ = std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(
        processor_.parameters(), ParamIds::source, source_);
    for (const auto& entry : processor_.sceneTable().scenes)
        scene_.addItem(juce::String(entry.scene) + (entry.available ? "" : " (unavailable)"), scene_.getNumItems() + 1);
    describe(scene_, "Scene", "The application the arm plays: theremin, cymbal, panel, braille and the others. "
                              "Arrows or Return open the list.");
    sceneAttachment_ = std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(
        processor_.parameters(), ParamIds::scene, scene_);
    // The program menu: the factory presets (the host's programs), here for the standalone app too.
    for (int i = 0; i < processor_.getNumPrograms(); ++i) preset_.addItem(processor_.getProgramName(i), i + 1);
    preset_.setTextWhenNothingSelected("choose a preset");
    describe(preset_, "Preset", "Factory presets (the programs): each sets a scene and its settings; the source stays yours.");
    preset_.onChange = [this] {
        const int index = preset_.getSelectedId() - 1;
        if (index >= 0 && index != processor_.getCurrentProgram()) processor_.setCurrentProgram(index);
    };
    sourceLabel_.attachToComponent(&source_, true);
    sceneLabel_.attachToComponent(&scene_, true);
    presetLabel_.attachToComponent(&preset_, true);
    describe(wander_, "Simulator wandering", "When on, the simulated arm wanders by itself; moving it by hand switches this off.");
    wander_.getToggleStateValue().referTo(processor_.settings().getPropertyAsValue(SettingIds::simWandering, nullptr));
    describe(status_, "Message", "The latest problem or notice; it goes away when it no longer holds, or with OK.");
    status_.setColour(juce::Label::backgroundColourId, juce::Colour(0xff5a3a12));
    describe(statusLine_, "Status", "Which source drives the arm and how many samples per second arrive, whether audio is "
                                    "flowing, the audio input when the scene listens, and whether the motors are driven.");
    statusLine_.setColour(juce::Label::backgroundColourId, juce::Colour(0xff111820));
    statusLine_.setColour(juce::Label::textColourId, juce::Colour(0xffd8e4ee));
    statusLine_.setJustificationType(juce::Justification::centredLeft);
    statusLine_.setMinimumHorizontalScale(1.0f);
    describe(dismiss_, "Dismiss message", "Hide the message.");
    dismiss_.onClick = [this] { processor_.clearStatusMessage(); timerCallback(); };
    describe(about_, "About ARMadillo", "Version, licence and where your own scores go.");
    about_.onClick = [] {
        const juce::String version {std::string(core::kVersion)};
        juce::AlertWindow::showMessageBoxAsync(
            juce::MessageBoxIconType::InfoIcon, "About ARMadillo",
            "ARMadillo " + version + " - forearm controller and tactile display (after D. Sachs, MIT 2005).\n\n"
                "Licence: GPL-3.0-or-later (it is built with JUCE 7 from Debian, which is GPL-3.0).\n\n"
                "Your own scores: " + juce::String(core::userResourceDir()) + "/Scores/NAME.score\n"
                "Documentation: /usr/share/doc/armadillo (installed) or docs/ in the sources.");
    };
    describe(help_, "Help", "Opens the welcome page again: what plays, how to hear it, connecting an arm or a phone (F1).");
    help_.onClick = [this] { showHelp(); };
    describe(setup_, "Setup", "Save the whole setup (scene, parameters, device, mount, OSC) to a file, or load one.");
    setup_.onClick = [this] { showSetupMenu(); };
    describe(stage_, "Stage", "On stage: the performance view (F11), load or clear a set list, panic (F12) and resume, the panic gesture.");
    stage_.onClick = [this] { showStageMenu(); };
    describe(mappingButton_, "Mapping editor", "Open the mapping editor: arm features to MIDI, OSC, macros and scene parameters, with MIDI learn.");
    mappingButton_.onClick = [this] { openWindow(mappingWindow_, [this] { return std::make_unique<MappingPanel>(processor_); }, {760, 520}, "ARMadillo mapping"); };
    describe(readerButton_, "Reader settings", "Self-voicing and braille display, the reader's touch profile, the progress report.");
    readerButton_.onClick = [this] {
        // The adaptive training's choices take two rows; the messages below.
        openWindow(readerWindow_, [this] { return std::make_unique<ReaderPanel>(processor_); }, {640, 860}, "ARMadillo reader");
    };

    deviceView_.setViewedComponent(&device_, false);
    deviceView_.setScrollBarsShown(true, false);
    deviceView_.setTitle("Device and OSC settings");
    deviceView_.setDescription("The device panel; it scrolls (Page Up / Page Down, or Tab through it) when the window is low.");

    for (juce::Component* c : std::initializer_list<juce::Component*> {&source_, &scene_, &preset_, &wander_, &readerButton_, &mappingButton_, &stage_, &setup_, &help_, &about_,
                                                                        &armView_, &motors_, &deviceView_, &sceneControls_, &statusLine_})
        addAndMakeVisible(*c);
    armView_.setWantsKeyboardFocus(true);
    motors_.setWantsKeyboardFocus(true);
    addChildComponent(status_);
    training_.onWantedChange = [this] {
        training_.setVisible(training_.wanted());
        resized();
    };
    training_.onLeave = [this] {
        if (scene_.isShowing()) scene_.grabKeyboardFocus();
    };
    addChildComponent(training_);
    addChildComponent(dismiss_);
    addChildComponent(welcome_);
    addChildComponent(performance_);
    performance_.onClose = [this] {
        if (stage_.isShowing()) stage_.grabKeyboardFocus();
    };
    welcome_.onShowDevice = [this] { device_.focusDevice(); };
    welcome_.onShowOsc = [this] { device_.focusOscInput(); };
    welcome_.onClose = [this] {
        if (! help_.hasKeyboardFocus(false) && isShowing()) help_.grabKeyboardFocus();
    };

    // Tab order: the top bar left to right, the message, then the panels as laid out (arm view,
    // training, motors, device, scene controls) and the status line last.
    int order = 1;
    for (juce::Component* c : std::initializer_list<juce::Component*> {&source_, &scene_, &preset_, &wander_, &readerButton_, &mappingButton_, &stage_, &setup_, &help_, &about_,
                                                                        &status_, &dismiss_, &armView_, &training_, &motors_,
                                                                        &deviceView_, &sceneControls_, &statusLine_})
        c->setExplicitFocusOrder(order++);
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);
    juce::Desktop::getInstance().addFocusChangeListener(this);

    // Read the saved size before the limits are set: setting them resizes (and saves) at once.
    const int width = static_cast<int>(processor_.settings()[SettingIds::editorWidth]);
    const int height = static_cast<int>(processor_.settings()[SettingIds::editorHeight]);
    setResizable(true, true);
    setResizeLimits(720, 520, 4000, 3000);
    setSize(juce::jlimit(720, 4000, width), juce::jlimit(520, 3000, height));
    timerCallback();
    startTimerHz(10);
    // The app's first start explains itself (a plugin's welcome waits for Help: a DAW user opened it on purpose).
    if (processor_.wrapperType == juce::AudioProcessor::wrapperType_Standalone && WelcomePanel::showAtStart())
        juce::MessageManager::callAsync([safe = juce::Component::SafePointer<ArmadilloEditor>(this)] {
            if (safe != nullptr) safe->showHelp();
        });
}

ArmadilloEditor::~ArmadilloEditor()
{
    if (mappingWindow_ != nullptr) delete mappingWindow_.getComponent();   // its panel uses the processor
    juce::Desktop::getInstance().removeFocusChangeListener(this);
    if (readerWindow_ != nullptr) delete readerWindow_.getComponent();
    if (tactorsWindow_ != nullptr) delete tactorsWindow_.getComponent();
    if (navigationWindow_ != nullptr) delete navigationWindow_.getComponent();
    if (mqttWindow_ != nullptr) delete mqttWindow_.getComponent();
    if (webWindow_ != nullptr) delete webWindow_.getComponent();
    sourceAttachment_.reset();
    sceneAttachment_.reset();
}

void ArmadilloEditor::showHelp()
{
    resized();
    welcome_.open();
}

void ArmadilloEditor::showPerformance()
{
    resized();
    performance_.open();
}

void ArmadilloEditor::showStageMenu()
{
    const auto info = processor_.stageInfo();
    juce::PopupMenu menu;
    menu.addItem(1, "Performance view (F11)");
    menu.addSeparator();
    menu.addItem(2, "Load set list...");
    menu.addItem(3, "Clear set list" + (info.setList ? " (" + juce::String(info.listName) + ")" : juce::String()), info.setList);
    menu.addSeparator();
    menu.addItem(4, "Panic (F12)", ! info.panicked);
    menu.addItem(5, "Resume", info.panicked);
    menu.addSeparator();
    const bool oscOn = static_cast<bool>(processor_.settings()[SettingIds::stageOscEnabled]);
    menu.addItem(6, "OSC stage commands on UDP " + processor_.settings()[SettingIds::stageOscPort].toString(), true, oscOn);
    const bool gestureOn = static_cast<bool>(processor_.settings()[SettingIds::panicGesture]);
    menu.addItem(7, "Panic gesture: arm hanging down for 2 s", true, gestureOn);
    menu.showMenuAsync(juce::PopupMenu::Options().withTargetComponent(&stage_), [this](int choice) {
        switch (choice) {
        case 1: showPerformance(); break;
        case 2: chooseSetList(); break;
        case 3: processor_.clearSetList(); break;
        case 4: processor_.panic(); break;
        case 5: processor_.resume(); break;
        case 6:
            processor_.settings().setProperty(SettingIds::stageOscEnabled, ! static_cast<bool>(processor_.settings()[SettingIds::stageOscEnabled]), nullptr);
            break;
        case 7:
            processor_.settings().setProperty(SettingIds::panicGesture, ! static_cast<bool>(processor_.settings()[SettingIds::panicGesture]), nullptr);
            break;
        default: break;
        }
    });
}

void ArmadilloEditor::chooseSetList()
{
    chooser_ = std::make_unique<juce::FileChooser>("Load a set list", setupFolder(), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::canSelectFiles | juce::FileBrowserComponent::openMode, [this](const juce::FileChooser& fc) {
        if (stage_.isShowing()) stage_.grabKeyboardFocus();   // the keys (F11, F12) work again at once
        const auto file = fc.getResult();
        if (file == juce::File()) return;
        if (const auto why = processor_.loadSetList(file); why.isNotEmpty()) {
            juce::AlertWindow::showMessageBoxAsync(juce::MessageBoxIconType::WarningIcon, "Load set list", why);
            plugin::announce(processor_, "stage", why, juce::AccessibilityHandler::AnnouncementPriority::medium);
        }
    });
}

void ArmadilloEditor::openWindow(juce::Component::SafePointer<juce::DialogWindow>& window, const std::function<std::unique_ptr<juce::Component>()>& make,
                                 juce::Point<int> size, const juce::String& title)
{
    if (window != nullptr) {   // one of each: brought to the front
        window->toFront(true);
        return;
    }
    juce::DialogWindow::LaunchOptions o;
    auto panel = make();
    panel->setSize(size.x, size.y);
    o.content.setOwned(panel.release());
    o.dialogTitle = title;
    o.resizable = true;
    o.useNativeTitleBar = true;
    o.escapeKeyTriggersCloseButton = true;
    window = o.launchAsync();
}

void ArmadilloEditor::showTactors()
{
    openWindow(tactorsWindow_, [this] { return std::make_unique<TactorsPanel>(processor_); }, {640, 380}, "ARMadillo tactors");
}

void ArmadilloEditor::showNavigation()
{
    openWindow(navigationWindow_, [this] { return std::make_unique<NavigationPanel>(processor_); }, {640, 460}, "ARMadillo navigation");
}

void ArmadilloEditor::showMqtt()
{
    openWindow(mqttWindow_, [this] { return std::make_unique<MqttPanel>(processor_); }, {640, 330}, "ARMadillo MQTT messages");
}

void ArmadilloEditor::showWebPage()
{
    openWindow(webWindow_, [this] { return std::make_unique<WebPanel>(processor_); }, {640, 400}, "ARMadillo web page");
}

void ArmadilloEditor::showSetupMenu()
{
    juce::PopupMenu menu;
    menu.addItem(1, "Save setup...");
    menu.addItem(2, "Load setup...");
    menu.addSeparator();
    menu.addItem(3, "Tactors...");
    menu.addItem(4, "Navigation...");
    menu.addItem(5, "MQTT messages...");
    menu.addItem(6, "Web page...");
    menu.showMenuAsync(juce::PopupMenu::Options().withTargetComponent(&setup_), [this](int choice) {
        if (choice == 3) showTactors();
        if (choice == 4) showNavigation();
        if (choice == 5) showMqtt();
        if (choice == 6) showWebPage();
        if (choice != 1 && choice != 2) return;
        const bool save = choice == 1;
        const auto folder = setupFolder();
        chooser_ = std::make_unique<juce::FileChooser>(save ? "Save the setup as" : "Load a setup",
                                                       save ? folder.getChildFile("my-setup.armadillo") : folder, "*.armadillo");
        const int flags = juce::FileBrowserComponent::canSelectFiles
                          | (save ? juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::warnAboutOverwriting
                                  : juce::FileBrowserComponent::openMode);
        chooser_->launchAsync(flags, [this, save](const juce::FileChooser& fc) {
            const auto file = fc.getResult();
            if (file == juce::File()) return;
            const auto target = save && ! file.hasFileExtension("armadillo") ? file.withFileExtension("armadillo") : file;
            const auto why = save ? processor_.saveSetup(target) : processor_.loadSetup(target);
            const auto title = save ? juce::String("Save setup") : juce::String("Load setup");
            const auto text = why.isNotEmpty() ? why
                                               : (save ? "The setup was saved to " : "The setup was loaded from ") + target.getFullPathName();
            juce::AlertWindow::showMessageBoxAsync(why.isNotEmpty() ? juce::MessageBoxIconType::WarningIcon : juce::MessageBoxIconType::InfoIcon,
                                                   title, text);
            plugin::announce(processor_, "setup", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
        });
    });
}

void ArmadilloEditor::timerCallback()
{
    const auto message = processor_.statusMessage();
    if (message != status_.getText()) {
        status_.setText(message, juce::dontSendNotification);
        processor_.speakAnnouncement(message, false);   // a status change is spoken and brailled too
        status_.setVisible(message.isNotEmpty());
        dismiss_.setVisible(message.isNotEmpty());
        resized();
    }
    wander_.setEnabled(processor_.source() == SourceKind::Simulator);
    if (const int program = processor_.getCurrentProgram() + 1; program != preset_.getSelectedId())
        preset_.setSelectedId(program, juce::dontSendNotification);
    updateStatusLine();
    // The ring follows a focused control that scrolls or moves.
    if (const auto ring = focusRingArea(); ring != lastRing_) {
        repaint(lastRing_.expanded(4));
        repaint(ring.expanded(4));
        lastRing_ = ring;
    }
}

void ArmadilloEditor::updateStatusLine()
{
    live::StatusSnapshot s;
    s.now = juce::Time::getMillisecondCounterHiRes() * 1.0e-3;
    s.source = processor_.source();
    s.sourceSamples = processor_.sourceSamples(s.source);
    s.deviceConnected = processor_.deviceConnected();
    s.deviceName = processor_.settings()[SettingIds::serialPort].toString().toStdString();
    s.oscPort = static_cast<bool>(processor_.settings()[SettingIds::oscInEnabled]) ? static_cast<int>(processor_.settings()[SettingIds::oscInPort]) : 0;
    s.leftArmPort = processor_.leftArmOn() ? processor_.leftArmPort() : 0;   // issue 28: the left arm's sender
    s.leftArmSamples = processor_.leftArmSamples();
    s.audioBlocks = processor_.audioBlocks();
    s.outputPeak = processor_.takeOutputPeak();
    s.listens = processor_.sceneListens();
    s.inputPeak = processor_.takeInputPeak();
    s.inputMuted = standaloneAudio().inputMuted;
    const auto frame = processor_.latestFrame();
    s.motorCount = frame.motorCount;
    for (int i = 0; i < frame.motorCount && i < static_cast<int>(frame.motors.size()); ++i)
        if (frame.motors[static_cast<std::size_t>(i)] > 0) ++s.motorsActive;
    const juce::String line(statusTracker_.update(s));
    if (line != statusLine_.getText()) statusLine_.setText(line, juce::dontSendNotification);
}

bool ArmadilloEditor::keyPressed(const juce::KeyPress& key)
{
    if (key == juce::KeyPress::F1Key) {
        showHelp();
        return true;
    }
    if (key == juce::KeyPress::F11Key) {
        showPerformance();
        return true;
    }
    if (key == juce::KeyPress::F12Key) {   // the panic key (docs/STAGE.md): no control uses it, so it works from anywhere
        processor_.panic();
        return true;
    }
    return false;   // nothing global: arrows and the rest act on the focused control only
}

void ArmadilloEditor::mouseDown(const juce::MouseEvent&)
{
    // A click on the background takes the focus away from the last control, so keys pressed
    // next cannot change a setting the eye has left.
    juce::Component::unfocusAllComponents();
}

void ArmadilloEditor::globalFocusChanged(juce::Component* focused)
{
    if (focused != nullptr && isParentOf(focused)) scrollIntoView(*focused);
    repaint(lastRing_.expanded(4));
    lastRing_ = focusRingArea();
    repaint(lastRing_.expanded(4));
}

void ArmadilloEditor::scrollIntoView(juce::Component& focused)
{
    // Tab into a scrolled panel: move its viewport so the focused control shows.
    for (auto* p = focused.getParentComponent(); p != nullptr && p != this; p = p->getParentComponent()) {
        auto* view = dynamic_cast<juce::Viewport*>(p);
        if (view == nullptr || view->getViewedComponent() == nullptr) continue;
        const auto area = view->getViewedComponent()->getLocalArea(&focused, focused.getLocalBounds());
        auto pos = view->getViewPosition();
        if (area.getY() < pos.y) pos.y = area.getY();
        else if (area.getBottom() > pos.y + view->getViewHeight()) pos.y = area.getBottom() - view->getViewHeight();
        view->setViewPosition(pos);
    }
}

juce::Rectangle<int> ArmadilloEditor::focusRingArea() const
{
    auto* focused = juce::Component::getCurrentlyFocusedComponent();
    if (focused == nullptr || ! isParentOf(focused) || ! focused->isShowing()) return {};
    auto area = getLocalArea(focused, focused->getLocalBounds());
    // Clipped to the viewports it sits in (a control scrolled half out of view).
    for (auto* p = focused->getParentComponent(); p != nullptr && p != this; p = p->getParentComponent())
        if (dynamic_cast<juce::Viewport*>(p) != nullptr) area = area.getIntersection(getLocalArea(p, p->getLocalBounds()));
    return area;
}

void ArmadilloEditor::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff0c1015));
}

void ArmadilloEditor::paintOverChildren(juce::Graphics& g)
{
    if (const auto ring = focusRingArea(); ! ring.isEmpty()) paintFocusRing(g, ring);
}

void ArmadilloEditor::resized()
{
    auto r = getLocalBounds().reduced(6);
    const int bar = juce::jlimit(28, 48, getHeight() / 20);
    const float font = juce::jlimit(13.0f, 20.0f, bar * 0.5f);

    // Status line at the bottom: two lines when narrow, one when wide.
    statusLine_.setFont(juce::Font(font - 1.0f));
    const int statusLines = juce::Font(font - 1.0f).getStringWidthFloat(statusLine_.getText()) > r.getWidth() - 30 ? 2 : 1;
    // (its right end leaves room for the window's resize corner)
    statusLine_.setBounds(r.removeFromBottom(juce::roundToInt((font + 3.0f) * static_cast<float>(statusLines)) + 6).withTrimmedRight(16));
    r.removeFromBottom(4);
    // The welcome covers everything but the status line (which it talks about).
    welcome_.setBounds(r.withSizeKeepingCentre(juce::jmin(r.getWidth() - 20, 760), juce::jmin(r.getHeight() - 10, 600)));
    performance_.setBounds(r);   // the performance view too, full size: it is read from afar

    // Top bar: the labels sit left of their boxes (attachToComponent); the boxes share what is left.
    // When the buttons would leave the three boxes less than 120 px each, they get a row of their own.
    auto top = r.removeFromTop(bar);
    const auto textWidth = [&](const juce::String& s) { return juce::roundToInt(juce::Font(font).getStringWidthFloat(s)) + 14; };
    const int labelsW = textWidth("Source") + textWidth("Scene") + textWidth("Preset");
    const int buttonsW = textWidth("Wander") + 24 + textWidth("Reader...") + textWidth("Mapping...") + textWidth("Stage...") + textWidth("Setup...") +
                         textWidth("Help") + textWidth("About") + 7 * 6;
    const int titleW = textWidth("ARMadillo") + 10;
    const bool twoRows = top.getWidth() - labelsW - buttonsW < 3 * 120;
    const bool showTitle = ! twoRows && top.getWidth() - labelsW - buttonsW - titleW >= 3 * 150;
    title_.setVisible(showTitle);
    if (showTitle) title_.setBounds(top.removeFromLeft(titleW));
    juce::Rectangle<int> buttonRow;
    if (twoRows) {
        r.removeFromTop(4);
        buttonRow = r.removeFromTop(bar);
    }
    auto& row = twoRows ? buttonRow : top;
    about_.setBounds(row.removeFromRight(textWidth("About")));
    row.removeFromRight(6);
    help_.setBounds(row.removeFromRight(textWidth("Help")));
    row.removeFromRight(6);
    setup_.setBounds(row.removeFromRight(textWidth("Setup...")));
    row.removeFromRight(6);
    stage_.setBounds(row.removeFromRight(textWidth("Stage...")));
    row.removeFromRight(6);
    mappingButton_.setBounds(row.removeFromRight(textWidth("Mapping...")));
    row.removeFromRight(6);
    readerButton_.setBounds(row.removeFromRight(textWidth("Reader...")));
    row.removeFromRight(6);
    wander_.setBounds(row.removeFromRight(textWidth("Wander") + 24));
    row.removeFromRight(6);
    const int box = juce::jmin(220, (top.getWidth() - labelsW) / 3);
    for (auto* pair : {&source_, &scene_, &preset_}) {
        auto* label = pair == &source_ ? &sourceLabel_ : pair == &scene_ ? &sceneLabel_ : &presetLabel_;
        label->setFont(juce::Font(font));
        top.removeFromLeft(textWidth(label->getText()));
        pair->setBounds(top.removeFromLeft(box).reduced(0, 2));
    }
    r.removeFromTop(4);
    if (status_.isVisible()) {
        // The message wraps: as many lines as it needs (at most four).
        const int lines = juce::jlimit(1, 4, juce::roundToInt(std::ceil(juce::Font(font).getStringWidthFloat(status_.getText())
                                                                        / juce::jmax(1.0f, r.getWidth() - 70.0f))));
        auto s = r.removeFromTop(juce::jmax(bar, juce::roundToInt((font + 4.0f) * lines) + 6));
        dismiss_.setBounds(s.removeFromRight(60).withSizeKeepingCentre(60, bar));
        status_.setFont(juce::Font(font));
        status_.setBounds(s);
        r.removeFromTop(4);
    }
    auto right = r.removeFromRight(juce::jlimit(340, 640, r.getWidth() * 2 / 5));
    r.removeFromRight(6);
    if (training_.isVisible()) {
        // The arm view gives up its lower part: a reader in training needs the prompt, not the sphere.
        training_.setBounds(r.removeFromBottom(juce::jlimit(180, 300, r.getHeight() / 2)));
        r.removeFromBottom(6);
    }
    armView_.setBounds(r);
    motors_.setBounds(right.removeFromTop(juce::jmax(170, right.getHeight() * 3 / 10)));   // its four rows stay legible
    right.removeFromTop(6);
    const auto deviceArea = right.removeFromTop(right.getHeight() * 3 / 5);
    deviceView_.setBounds(deviceArea);
    const bool scrolls = deviceArea.getHeight() < DevicePanel::kMinimumHeight;
    device_.setSize(deviceArea.getWidth() - (scrolls ? deviceView_.getScrollBarThickness() : 0),
                    juce::jmax(deviceArea.getHeight(), DevicePanel::kMinimumHeight));
    right.removeFromTop(6);
    sceneControls_.setBounds(right);
    processor_.settings().setProperty(SettingIds::editorWidth, getWidth(), nullptr);
    processor_.settings().setProperty(SettingIds::editorHeight, getHeight(), nullptr);
}

} // namespace armadillo::plugin
