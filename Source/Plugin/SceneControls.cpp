#include "Plugin/SceneControls.h"
#include "Plugin/Controls.h"
#include "Plugin/PluginProcessor.h"
#include "Core/Resources.h"
#include "Formats/ScoreImport.h"

namespace armadillo::plugin {

SceneControls::SceneControls(ArmadilloProcessor& processor) : processor_(processor)
{
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    addAndMakeVisible(heading_);
    note_.setFont(juce::Font(13.0f));
    note_.setColour(juce::Label::textColourId, juce::Colours::lightgrey);
    addAndMakeVisible(note_);
    viewport_.setViewedComponent(&content_, false);
    viewport_.setScrollBarsShown(true, false);
    viewport_.setTitle("Scene controls");
    viewport_.setDescription("The current scene's settings; the list scrolls when it is longer than the panel.");
    addAndMakeVisible(viewport_);
    setTitle("Scene controls");
    setFocusContainerType(FocusContainerType::focusContainer);
    rebuild();
    startTimerHz(10);
}

SceneControls::~SceneControls()
{
    controls_.clear();   // attachments before the components they attach
}

void SceneControls::timerCallback()
{
    if (processor_.sceneIndex() != shownScene_) rebuild();
}

void SceneControls::rebuild()
{
    controls_.clear();
    content_.removeAllChildren();
    shownScene_ = processor_.sceneIndex();
    const auto& scenes = processor_.sceneTable().scenes;
    if (shownScene_ < 0 || shownScene_ >= static_cast<int>(scenes.size())) return;
    const auto& entry = scenes[static_cast<std::size_t>(shownScene_)];
    heading_.setText("Scene: " + juce::String(entry.scene), juce::dontSendNotification);
    note_.setText(entry.available ? (entry.specs.empty() ? "This scene has no settings." : "")
                                  : "Not available in this build: " + juce::String(entry.reason),
                  juce::dontSendNotification);

    auto& apvts = processor_.parameters();
    for (std::size_t i = 0; i < entry.specs.size(); ++i) {
        if (! entry.exposed[i]) continue;
        const auto& spec = entry.specs[i];
        const auto id = juce::String(spec.id);
        Control c;
        const auto name = juce::String(spec.name.empty() ? spec.id : spec.name);
        c.label = std::make_unique<juce::Label>();
        c.label->setText(name + (spec.unit.empty() ? "" : " (" + juce::String(spec.unit) + ")"), juce::dontSendNotification);
        if (! spec.choices.empty()) {
            auto box = std::make_unique<ChoiceBox>();
            int itemId = 1;
            for (const auto& choice : spec.choices) box->addItem(juce::String(choice), itemId++);
            c.combo = std::make_unique<juce::AudioProcessorValueTreeState::ComboBoxAttachment>(apvts, id, *box);
            c.editor = std::move(box);
        } else {
            auto slider = std::make_unique<ValueSlider>(juce::Slider::LinearHorizontal, juce::Slider::TextBoxRight);
            // The value shows beside the slider, read-only: the slider itself takes the keys (arrows,
            // Page Up/Down, Home/End) and is the one Tab stop, with the value as its accessible value.
            slider->setTextBoxStyle(juce::Slider::TextBoxRight, true, 80, 20);
            c.slider = std::make_unique<juce::AudioProcessorValueTreeState::SliderAttachment>(apvts, id, *slider);
            c.editor = std::move(slider);
        }
        c.editor->setTitle(name);
        c.editor->setDescription(juce::String(entry.scene) + " setting " + id
                                 + (spec.unit.empty() ? juce::String() : ", in " + juce::String(spec.unit)));
        c.editor->setWantsKeyboardFocus(true);
        content_.addAndMakeVisible(*c.label);
        content_.addAndMakeVisible(*c.editor);
        controls_.push_back(std::move(c));
    }

    auto addTextSetting = [&](const juce::Identifier& settingId, const juce::String& title, const juce::String& description) {
        Control c;
        c.label = std::make_unique<juce::Label>();
        c.label->setText(title, juce::dontSendNotification);
        auto editor = std::make_unique<juce::TextEditor>();
        editor->getTextValue().referTo(processor_.settings().getPropertyAsValue(settingId, nullptr));
        editor->setTitle(title);
        editor->setDescription(description);
        c.editor = std::move(editor);
        content_.addAndMakeVisible(*c.label);
        content_.addAndMakeVisible(*c.editor);
        controls_.push_back(std::move(c));
    };
    if (entry.scene == "braille")
        addTextSetting(SettingIds::brailleText, "Text to read", "What the braille scene shows on the arm, one character at a time.");
    if (entry.scene == "score") {
        // The scores found by name (the shipped ones and the user's own Scores/*.score in
        // ~/.local/share/armadillo or $ARMADILLO_RESOURCES); a path can be typed as well.
        Control c;
        c.label = std::make_unique<juce::Label>();
        c.label->setText("Score", juce::dontSendNotification);
        auto box = std::make_unique<ChoiceBox>();
        int itemId = 1;
        for (const core::ScoreEntry& s : core::listScores()) box->addItem(juce::String(s.name), itemId++);
        box->addSeparator();
        constexpr int kImportItem = 10000;
        box->addItem("Import a file... (MIDI, WAV, AHAP, .haptic, .tact, .hjif)", kImportItem);
        box->setEditableText(true);
        box->setText(processor_.settings()[SettingIds::score].toString(), juce::dontSendNotification);
        box->setTitle("Score");
        box->setDescription("A score by name (the shipped ones and yours in " + juce::String(core::userResourceDir())
                            + "/Scores), the path of a .score file, or Import a file: a MIDI file, a multichannel WAV, an AHAP, a .haptic, a bHaptics .tact or an MPEG .hjif file.");
        box->onChange = [this, b = box.get()] {
            if (b->getSelectedId() == kImportItem) {
                chooseScoreFile(*b);
                return;
            }
            if (b->getText().isNotEmpty()) processor_.settings().setProperty(SettingIds::score, b->getText(), nullptr);
        };
        c.editor = std::move(box);
        content_.addAndMakeVisible(*c.label);
        content_.addAndMakeVisible(*c.editor);
        controls_.push_back(std::move(c));
    }
    resized();
}

void SceneControls::chooseScoreFile(juce::ComboBox& box)
{
    const juce::String current = processor_.settings()[SettingIds::score].toString();
    box.setText(current, juce::dontSendNotification);   // until a file is chosen and imports
    chooser_ = std::make_unique<juce::FileChooser>("Import a score from a MIDI, WAV, AHAP, .haptic, .tact or .hjif file",
                                                   juce::File::getSpecialLocation(juce::File::userMusicDirectory),
                                                   "*.mid;*.midi;*.wav;*.ahap;*.haptic;*.tact;*.hjif;*.score");
    juce::Component::SafePointer<juce::ComboBox> safeBox(&box);
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles,
                          [this, safeBox](const juce::FileChooser& fc) {
                              const juce::File f = fc.getResult();
                              if (f == juce::File()) return;
                              const std::string path = f.getFullPathName().toStdString();
                              try {
                                  // The same import the engine runs as it loads: its errors name the file and the byte or line.
                                  const formats::ImportedScore s = formats::importScoreFile(path);
                                  processor_.settings().setProperty(SettingIds::score, juce::String(path), nullptr);
                                  if (safeBox != nullptr) safeBox->setText(juce::String(path), juce::dontSendNotification);
                                  note_.setText("Imported " + f.getFileName() + ": " + juce::String(s.report.notes) + " notes, " +
                                                    juce::String(s.score.length, 1) + " s",
                                                juce::dontSendNotification);
                              } catch (const std::exception& e) {
                                  note_.setText("Not imported: " + juce::String(e.what()), juce::dontSendNotification);
                                  juce::AlertWindow::showMessageBoxAsync(juce::MessageBoxIconType::WarningIcon, "Score not imported",
                                                                         juce::String(e.what()));
                              }
                              resized();
                          });
}

void SceneControls::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff161c24));
}

void SceneControls::resized()
{
    auto r = getLocalBounds().reduced(6);
    heading_.setBounds(r.removeFromTop(24));
    if (note_.getText().isNotEmpty()) note_.setBounds(r.removeFromTop(22));
    else note_.setBounds({});
    viewport_.setBounds(r);
    const int rowH = 28;
    const int width = std::max(100, r.getWidth() - viewport_.getScrollBarThickness());
    content_.setSize(width, rowH * static_cast<int>(controls_.size()) + 4);
    int y = 2;
    for (auto& c : controls_) {
        juce::Rectangle<int> row(0, y, width, rowH - 3);
        c.label->setBounds(row.removeFromLeft(width * 2 / 5));
        c.editor->setBounds(row);
        y += rowH;
    }
}

} // namespace armadillo::plugin
