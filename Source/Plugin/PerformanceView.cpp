#include "Plugin/PerformanceView.h"
#include "Plugin/Accessibility.h"   // describe(): title, description, focus (a screen reader lands on each line)
#include "Plugin/PluginProcessor.h"

namespace armadillo::plugin {

namespace {
juce::String sourceName(SourceKind kind)
{
    switch (kind) {
    case SourceKind::Device: return "device";
    case SourceKind::Simulator: return "simulator";
    case SourceKind::Osc: return "OSC";
    case SourceKind::HostAutomation: return "host automation";
    }
    return "?";
}
} // namespace

PerformanceView::PerformanceView(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Performance view");
    setDescription("The cue playing and the next one, each arm's source, the motors and the panic state, in large type. "
                   "Keys: N or Space next cue, B previous, P or Escape panic, R resume, 1 to 9 a cue, C closes.");
    setWantsKeyboardFocus(true);
    describe(panic_, "Panic", "Stops all sound, every note sent and every motor at once (P or Escape).");
    describe(resume_, "Resume", "Back to the current cue after a panic (R).");
    describe(previous_, "Previous cue", "Steps back one cue of the set list (B).");
    describe(next_, "Next cue", "Steps to the next cue of the set list (N or Space).");
    describe(close_, "Close the performance view", "Back to the editor (C).");
    panic_.setColour(juce::TextButton::buttonColourId, juce::Colour(0xffb01818));
    panic_.setColour(juce::TextButton::textColourOffId, juce::Colours::white);
    panic_.onClick = [this] { processor_.panic(); refresh(); };
    for (auto* b : {&panic_, &resume_, &previous_, &next_, &close_}) b->setLookAndFeel(&largeText_);
    resume_.onClick = [this] { processor_.resume(); refresh(); };
    previous_.onClick = [this] { processor_.previousCue(); };
    next_.onClick = [this] { processor_.nextCue(); };
    close_.onClick = [this] { close(); };
    for (auto* label : {&cue_, &nextCue_, &arms_, &state_}) {
        label->setColour(juce::Label::textColourId, juce::Colours::white);
        label->setJustificationType(juce::Justification::centredLeft);
        label->setMinimumHorizontalScale(0.6f);
        addAndMakeVisible(*label);
    }
    describe(cue_, "Current cue", "The cue playing: its number of how many, its name and scene.");
    describe(nextCue_, "Coming next", "The cue Next goes to.");
    describe(arms_, "Arms", "Each arm's source, and whether its samples arrive (live) or not (silent).");
    describe(state_, "Panic state", "PANIC while everything is off; Playing otherwise.");
    int order = 1;
    for (juce::Component* c : std::initializer_list<juce::Component*> {&state_, &cue_, &nextCue_, &arms_, &panic_, &resume_, &previous_, &next_, &close_}) {
        addAndMakeVisible(*c);
        c->setExplicitFocusOrder(order++);
    }
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);
}

PerformanceView::~PerformanceView()
{
    for (auto* b : {&panic_, &resume_, &previous_, &next_, &close_}) b->setLookAndFeel(nullptr);
}

void PerformanceView::open()
{
    refresh();
    setVisible(true);
    toFront(false);
    startTimerHz(10);
    if (isShowing()) grabKeyboardFocus();
}

void PerformanceView::close()
{
    stopTimer();
    setVisible(false);
    if (onClose) onClose();
}

void PerformanceView::refresh()
{
    const auto info = processor_.stageInfo();
    if (info.setList) {
        cueLine_ = "Cue " + juce::String(info.cue + 1) + "/" + juce::String(info.cueCount) + ": " + juce::String(info.cueName) + "  ("
                   + juce::String(info.cueScene) + ")";
        nextLine_ = info.next >= 0 ? "Next " + juce::String(info.next + 1) + ": " + juce::String(info.nextName) + "  (" + juce::String(info.nextScene) + ")"
                                   : juce::String("Next: none (last cue)");
    } else {
        const auto& scenes = processor_.sceneTable().scenes;
        const int index = processor_.sceneIndex();
        const juce::String scene = index >= 0 && index < static_cast<int>(scenes.size()) ? juce::String(scenes[static_cast<std::size_t>(index)].scene)
                                                                                         : juce::String("?");
        cueLine_ = "No set list: scene " + scene;
        nextLine_ = "Next: none (Stage > Load set list...)";
    }
    // The arm's source as the status line counts it: live while samples keep coming.
    live::StatusSnapshot s;
    s.now = juce::Time::getMillisecondCounterHiRes() * 1.0e-3;
    s.source = processor_.source();
    s.sourceSamples = processor_.sourceSamples(s.source);
    s.deviceConnected = processor_.deviceConnected();
    s.audioBlocks = processor_.audioBlocks();
    s.leftArmPort = processor_.leftArmOn() ? processor_.leftArmPort() : 0;
    s.leftArmSamples = processor_.leftArmSamples();
    sourceTracker_.update(s);
    const bool automation = s.source == SourceKind::HostAutomation;
    const auto left = processor_.settings()[SettingIds::armSide].toString() == "left";
    const juce::String arm = sourceName(s.source) + (automation ? juce::String() : sourceTracker_.sourceSilent() ? " SILENT" : " live");
    if (s.leftArmPort > 0)   // two arms (issue 28): the left arm's OSC sender
        armLine_ = "Right arm: " + arm + "   Left arm: OSC port " + juce::String(s.leftArmPort)
                   + (sourceTracker_.leftArmSilent() ? " SILENT" : " live");
    else
        armLine_ = left ? "Left arm: " + arm + "   Right: none" : "Right arm: " + arm + "   Left: none";
    stateLine_ = info.panicked ? juce::String("PANIC - all off") : juce::String("Playing");
    const auto f = processor_.latestFrame();
    if (f.motors != levels_ || f.motorCount != motorCount_) {
        levels_ = f.motors;
        motorCount_ = f.motorCount;
        repaint(motorArea());
    }
    cue_.setText(cueLine_, juce::dontSendNotification);
    nextCue_.setText(nextLine_, juce::dontSendNotification);
    arms_.setText(armLine_, juce::dontSendNotification);
    state_.setText(stateLine_, juce::dontSendNotification);
    state_.setColour(juce::Label::backgroundColourId, info.panicked ? juce::Colour(0xffb01818) : juce::Colour(0xff1d5a2a));
    const bool cues = info.setList;
    previous_.setEnabled(cues);
    next_.setEnabled(cues);
    resume_.setEnabled(info.panicked);
}

bool PerformanceView::keyPressed(const juce::KeyPress& key)
{
    // The typed character, else the key code (letters: either case; digits: the digit).
    const auto c = key.getTextCharacter() != 0 ? key.getTextCharacter() : static_cast<juce::juce_wchar>(key.getKeyCode());
    if (key == juce::KeyPress::escapeKey || c == 'p' || c == 'P') processor_.panic();
    else if (c == 'r' || c == 'R') processor_.resume();
    else if (key == juce::KeyPress::spaceKey || c == 'n' || c == 'N') processor_.nextCue();
    else if (c == 'b' || c == 'B') processor_.previousCue();
    else if (c >= '1' && c <= '9') processor_.goToCue(c - '1');
    else if (c == 'c' || c == 'C') close();
    else return false;
    refresh();
    return true;
}

juce::Rectangle<int> PerformanceView::motorArea() const
{
    auto r = getLocalBounds().reduced(12);
    return r.removeFromRight(juce::jmin(r.getWidth() / 3, r.getHeight() * 3 / 5));
}

void PerformanceView::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff05080c));
    // The motors: three rows of three (wrist to elbow), the level in each cell.
    auto area = motorArea().toFloat();
    const float cell = juce::jmin(area.getWidth() / 3.0f, area.getHeight() / 3.2f);
    g.setColour(juce::Colours::white);
    g.setFont(juce::Font(cell * 0.22f, juce::Font::bold));
    g.drawText("Motors", area.removeFromTop(cell * 0.3f), juce::Justification::centredLeft);
    for (int i = 0; i < 9 && i < motorCount_; ++i) {
        const auto r = juce::Rectangle<float>(area.getX() + static_cast<float>(i % 3) * cell, area.getY() + static_cast<float>(i / 3) * cell, cell, cell)
                           .reduced(cell * 0.05f);
        const float level = static_cast<float>(levels_[static_cast<std::size_t>(i)]) / static_cast<float>(core::kMaxLevel);
        g.setColour(juce::Colour(0xff222c38).interpolatedWith(juce::Colour(0xffff8a3d), level));
        g.fillRoundedRectangle(r, cell * 0.1f);
        g.setColour(juce::Colours::white);
        g.setFont(juce::Font(cell * 0.45f, juce::Font::bold));
        g.drawText(juce::String(static_cast<int>(levels_[static_cast<std::size_t>(i)])), r, juce::Justification::centred);
    }
}

void PerformanceView::resized()
{
    auto r = getLocalBounds().reduced(12);
    r.removeFromRight(motorArea().getWidth() + 12);
    const int line = juce::jlimit(24, 140, r.getHeight() / 7);
    const float font = static_cast<float>(line) * 0.7f;
    state_.setFont(juce::Font(font, juce::Font::bold));
    state_.setBounds(r.removeFromTop(line));
    r.removeFromTop(line / 6);
    cue_.setFont(juce::Font(font, juce::Font::bold));
    cue_.setBounds(r.removeFromTop(line));
    nextCue_.setFont(juce::Font(font * 0.75f));
    nextCue_.setBounds(r.removeFromTop(line));
    arms_.setFont(juce::Font(font * 0.6f));
    arms_.setBounds(r.removeFromTop(line));
    r.removeFromTop(line / 6);
    auto buttons = r.removeFromBottom(juce::jmax(28, line * 2 / 3));
    r.removeFromBottom(line / 6);
    panic_.setBounds(r);   // the biggest thing on the screen
    const int w = (buttons.getWidth() - 3 * 8) / 4;
    for (auto* b : {&resume_, &previous_, &next_, &close_}) {
        b->setBounds(buttons.removeFromLeft(w));
        buttons.removeFromLeft(8);
    }
}

} // namespace armadillo::plugin
