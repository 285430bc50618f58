#include "Plugin/PluginEditor.h"
#include "Plugin/MappingPanel.h"
#include "Plugin/PluginProcessor.h"
#include "Plugin/ReaderPanel.h"
#include "Core/Resources.h"
#include "Core/Version.h"

namespace armadillo::plugin {

ArmadilloEditor::ArmadilloEditor(ArmadilloProcessor& processor)
    : AudioProcessorEditor(processor), processor_(processor), armView_(processor), motors_(processor),
      device_(processor), sceneControls_(processor), training_(processor)
{
    setTitle("ARMadillo");
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
    source_.addItemList(sourceChoiceNames(), 1);
    source_.setTitle("Source");
    source_.setDescription("Where the arm's orientation comes from: device, simulator, OSC or host automation.");
    sourceAttachment_ = std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(
        processor_.parameters(), ParamIds::source, source_);
    for (const auto& entry : processor_.sceneTable().scenes)
        scene_.addItem(juce::String(entry.scene) + (entry.available ? "" : " (unavailable)"), scene_.getNumItems() + 1);
    scene_.setTitle("Scene");
    scene_.setDescription("The application the arm plays: theremin, cymbal, panel, braille and the others.");
    sceneAttachment_ = std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(
        processor_.parameters(), ParamIds::scene, scene_);
    sourceLabel_.attachToComponent(&source_, true);
    sceneLabel_.attachToComponent(&scene_, true);
    wander_.setTitle("Simulator wandering");
    wander_.setDescription("When on, the simulated arm wanders by itself; moving it by hand switches this off.");
    wander_.getToggleStateValue().referTo(processor_.settings().getPropertyAsValue(SettingIds::simWandering, nullptr));
    status_.setTitle("Status message");
    status_.setColour(juce::Label::backgroundColourId, juce::Colour(0xff5a3a12));
    dismiss_.setTitle("Dismiss message");
    dismiss_.onClick = [this] { processor_.clearStatusMessage(); timerCallback(); };
    about_.setTitle("About ARMadillo");
    about_.setDescription("Version, licence and where your own scores go.");
    about_.onClick = [] {
        const juce::String version {std::string(kVersion)};
        juce::AlertWindow::showMessageBoxAsync(
            juce::MessageBoxIconType::InfoIcon, "About ARMadillo",
            "ARMadillo " + version + " - forearm controller and tactile display (after D. Sachs, MIT 2005).\n\n"
                "Licence: GPL-3.0-or-later (it is built with JUCE 7 from Debian, which is GPL-3.0).\n\n"
                "Your own scores: " + juce::String(userResourceDir()) + "/Scores/NAME.score\n"
                "Documentation: /usr/share/doc/armadillo (installed) or docs/ in the sources.");
    };
    addAndMakeVisible(about_);
    setup_.setTitle("Setup");
    setup_.setDescription("Save the whole setup (scene, parameters, device, mount, OSC) to a file, or load one.");
    setup_.onClick = [this] {
        juce::PopupMenu menu;
        menu.addItem(1, "Save setup...");
        menu.addItem(2, "Load setup...");
        menu.showMenuAsync(juce::PopupMenu::Options().withTargetComponent(&setup_), [this](int choice) {
            if (choice == 0) return;
            const bool save = choice == 1;
            chooser_ = std::make_unique<juce::FileChooser>(save ? "Save the setup as" : "Load a setup",
                                                           juce::File::getSpecialLocation(juce::File::userDocumentsDirectory), "*.armadillo");
            const int flags = juce::FileBrowserComponent::canSelectFiles
                              | (save ? juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::warnAboutOverwriting
                                      : juce::FileBrowserComponent::openMode);
            chooser_->launchAsync(flags, [this, save](const juce::FileChooser& fc) {
                const auto file = fc.getResult();
                if (file == juce::File()) return;
                const auto target = save && !file.hasFileExtension("armadillo") ? file.withFileExtension("armadillo") : file;
                const auto why = save ? processor_.saveSetup(target) : processor_.loadSetup(target);
                if (why.isNotEmpty())
                    juce::AlertWindow::showMessageBoxAsync(juce::MessageBoxIconType::WarningIcon, save ? "Save setup" : "Load setup", why);
            });
        });
    };
    addAndMakeVisible(setup_);
    mappingButton_.setTitle("Mapping editor");
    mappingButton_.setDescription("Open the mapping editor: arm features to MIDI, OSC, macros and scene parameters, with MIDI learn.");
    mappingButton_.onClick = [this] {
        if (mappingWindow_ != nullptr) {
            mappingWindow_->toFront(true);
            return;
        }
        juce::DialogWindow::LaunchOptions o;
        auto panel = std::make_unique<MappingPanel>(processor_);
        panel->setSize(760, 520);
        o.content.setOwned(panel.release());
        o.dialogTitle = "ARMadillo mapping";
        o.resizable = true;
        o.useNativeTitleBar = true;
        o.escapeKeyTriggersCloseButton = true;
        mappingWindow_ = o.launchAsync();
    };
    addAndMakeVisible(mappingButton_);
    readerButton_.setTitle("Reader settings");
    readerButton_.setDescription("Self-voicing and braille display, the reader's touch profile, the progress report.");
    readerButton_.onClick = [this] {
        if (readerWindow_ != nullptr) {
            readerWindow_->toFront(true);
            return;
        }
        juce::DialogWindow::LaunchOptions o;
        auto panel = std::make_unique<ReaderPanel>(processor_);
        panel->setSize(640, 600);
        o.content.setOwned(panel.release());
        o.dialogTitle = "ARMadillo reader";
        o.resizable = true;
        o.useNativeTitleBar = true;
        o.escapeKeyTriggersCloseButton = true;
        readerWindow_ = o.launchAsync();
    };
    addAndMakeVisible(readerButton_);

    for (juce::Component* c : std::initializer_list<juce::Component*> {&source_, &scene_, &wander_, &armView_, &motors_,
                                                                        &device_, &sceneControls_})
        c->setWantsKeyboardFocus(true), addAndMakeVisible(*c);
    addChildComponent(status_);
    training_.onWantedChange = [this] {
        training_.setVisible(training_.wanted());
        resized();
    };
    addChildComponent(training_);
    addChildComponent(dismiss_);
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);

    // Read the saved size before the limits are set: setting them resizes (and saves) at once.
    const int width = static_cast<int>(processor_.settings()[SettingIds::editorWidth]);
    const int height = static_cast<int>(processor_.settings()[SettingIds::editorHeight]);
    setResizable(true, true);
    setResizeLimits(720, 520, 4000, 3000);
    setSize(juce::jlimit(720, 4000, width), juce::jlimit(520, 3000, height));
    timerCallback();
    startTimerHz(5);
}

ArmadilloEditor::~ArmadilloEditor()
{
    if (mappingWindow_ != nullptr) delete mappingWindow_.getComponent();   // its panel uses the processor
    if (readerWindow_ != nullptr) delete readerWindow_.getComponent();
    sourceAttachment_.reset();
    sceneAttachment_.reset();
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
}

void ArmadilloEditor::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff0c1015));
}

void ArmadilloEditor::resized()
{
    auto r = getLocalBounds().reduced(6);
    const int bar = juce::jlimit(28, 48, getHeight() / 20);
    auto top = r.removeFromTop(bar);
    title_.setBounds(top.removeFromLeft(130));
    top.removeFromLeft(55);
    source_.setBounds(top.removeFromLeft(std::min(190, top.getWidth() / 3)));
    top.removeFromLeft(52);
    scene_.setBounds(top.removeFromLeft(std::min(190, top.getWidth() / 2)));
    top.removeFromLeft(10);
    // Four buttons and Wander share the rest (at the default 1040 px each still fits its text).
    about_.setBounds(top.removeFromRight(62));
    top.removeFromRight(4);
    setup_.setBounds(top.removeFromRight(72));
    top.removeFromRight(4);
    mappingButton_.setBounds(top.removeFromRight(86));
    top.removeFromRight(4);
    readerButton_.setBounds(top.removeFromRight(76));
    top.removeFromRight(4);
    wander_.setBounds(top.removeFromLeft(100));
    r.removeFromTop(4);
    if (status_.isVisible()) {
        auto s = r.removeFromTop(bar);
        dismiss_.setBounds(s.removeFromRight(60));
        status_.setBounds(s);
        r.removeFromTop(4);
    }
    auto right = r.removeFromRight(juce::jlimit(340, 640, r.getWidth() * 2 / 5));
    r.removeFromRight(6);
    if (training_.isVisible()) {
        // The arm view gives up its lower part: a reader in training needs the prompt, not the sphere.
        training_.setBounds(r.removeFromBottom(juce::jlimit(130, 190, r.getHeight() / 3)));
        r.removeFromBottom(6);
    }
    armView_.setBounds(r);
    motors_.setBounds(right.removeFromTop(right.getHeight() * 7 / 20));
    right.removeFromTop(6);
    device_.setBounds(right.removeFromTop(right.getHeight() * 3 / 5));
    right.removeFromTop(6);
    sceneControls_.setBounds(right);
    processor_.settings().setProperty(SettingIds::editorWidth, getWidth(), nullptr);
    processor_.settings().setProperty(SettingIds::editorHeight, getHeight(), nullptr);
}

} // namespace armadillo::plugin
