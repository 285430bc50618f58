#include "Plugin/PluginEditor.h"
#include "Plugin/PluginProcessor.h"

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
    sourceAttachment_.reset();
    sceneAttachment_.reset();
}

void ArmadilloEditor::timerCallback()
{
    const auto message = processor_.statusMessage();
    if (message != status_.getText()) {
        status_.setText(message, juce::dontSendNotification);
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
    title_.setBounds(top.removeFromLeft(150));
    top.removeFromLeft(60);
    source_.setBounds(top.removeFromLeft(std::min(200, top.getWidth() / 3)));
    top.removeFromLeft(60);
    scene_.setBounds(top.removeFromLeft(std::min(200, top.getWidth() / 2)));
    top.removeFromLeft(12);
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
