#include "Plugin/MotorDisplay.h"
#include "Plugin/PluginProcessor.h"

namespace armadillo::plugin {

namespace {
class LevelsValue : public juce::AccessibilityTextValueInterface {
public:
    explicit LevelsValue(MotorDisplay& d) : display_(d) {}
    bool isReadOnly() const override { return true; }
    juce::String getCurrentValueAsString() const override { return display_.describeLevels(); }
    void setValueAsString(const juce::String&) override {}

private:
    MotorDisplay& display_;
};
} // namespace

MotorDisplay::MotorDisplay(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Motor display");
    setDescription("Vibration level 0 to 15 of each motor: three rows from wrist to elbow, columns left, "
                   "underside and right, and the three back motors when enabled.");
    setWantsKeyboardFocus(true);   // so a screen reader user can land on it and read the levels
    startTimerHz(30);
}

std::unique_ptr<juce::AccessibilityHandler> MotorDisplay::createAccessibilityHandler()
{
    return std::make_unique<juce::AccessibilityHandler>(
        *this, juce::AccessibilityRole::image, juce::AccessibilityActions {},
        juce::AccessibilityHandler::Interfaces {std::make_unique<LevelsValue>(*this)});
}

juce::String MotorDisplay::describeLevels() const
{
    juce::String s;
    for (int i = 0; i < motorCount_; ++i)
        s << "motor " << (i + 1) << " " << static_cast<int>(levels_[static_cast<std::size_t>(i)]) << (i + 1 < motorCount_ ? ", " : "");
    return s;
}

void MotorDisplay::timerCallback()
{
    const auto f = processor_.latestFrame();
    const auto count = processor_.gestureCount();
    if (count != gestureCount_) {
        gestureCount_ = count;
        lastGesture_ = processor_.lastGesture();
        gestureFlash_ = 1.0;
    } else {
        gestureFlash_ = std::max(0.0, gestureFlash_ - 0.05);
    }
    if (f.motors != levels_ || f.motorCount != motorCount_ || gestureFlash_ > 0.0) {
        levels_ = f.motors;
        motorCount_ = f.motorCount;
        repaint();
    }
}

void MotorDisplay::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff141a22));
    auto area = getLocalBounds().toFloat().reduced(6.0f);
    const float text = juce::jlimit(11.0f, 28.0f, area.getHeight() * 0.06f);
    g.setFont(juce::Font(text, juce::Font::bold));
    g.setColour(juce::Colours::white);
    g.drawText("Motors", area.removeFromTop(text * 1.5f), juce::Justification::centredLeft);

    auto footer = area.removeFromBottom(text * 1.6f);
    auto back = area.removeFromBottom(area.getHeight() * 0.22f);
    const auto labelColumn = area.removeFromLeft(text * 3.8f);
    const float cell = std::min(area.getWidth() / 3.0f, area.getHeight() / 3.0f);
    const juce::Rectangle<float> grid(area.getX(), area.getY(), cell * 3.0f, cell * 3.0f);

    auto drawMotor = [&](juce::Rectangle<float> r, int index, bool enabled) {
        const float level = enabled ? levels_[static_cast<std::size_t>(index)] / static_cast<float>(core::kMaxLevel) : 0.0f;
        const auto hot = juce::Colour(0xffff8a3d).withBrightness(0.35f + 0.65f * level);
        g.setColour(enabled ? juce::Colour(0xff222c38).interpolatedWith(hot, level) : juce::Colour(0xff1b2028));
        g.fillRoundedRectangle(r.reduced(cell * 0.06f), cell * 0.12f);
        g.setColour(enabled ? juce::Colour(0xff6b7f94) : juce::Colour(0xff333a44));
        g.drawRoundedRectangle(r.reduced(cell * 0.06f), cell * 0.12f, 1.2f);
        g.setColour(enabled ? juce::Colours::white : juce::Colours::grey);
        g.setFont(juce::Font(std::max(10.0f, cell * 0.26f), juce::Font::bold));
        g.drawText(juce::String(enabled ? static_cast<int>(levels_[static_cast<std::size_t>(index)]) : 0), r, juce::Justification::centred);
        g.setFont(std::max(9.0f, cell * 0.14f));
        g.drawText("m" + juce::String(index + 1), r.reduced(cell * 0.14f), juce::Justification::topLeft);
    };

    static const char* rows[] {"wrist", "middle", "elbow"};
    g.setFont(text * 0.85f);
    for (int row = 0; row < 3; ++row) {
        g.setColour(juce::Colours::lightgrey);
        g.setFont(text * 0.85f);
        g.drawText(rows[row], labelColumn.withY(grid.getY() + cell * row).withHeight(cell), juce::Justification::centredLeft);
        for (int col = 0; col < 3; ++col)
            drawMotor({grid.getX() + cell * col, grid.getY() + cell * row, cell, cell}, core::motorIndex(row, col), true);
    }
    const float backCell = std::min(cell, back.getHeight());
    g.setColour(juce::Colours::lightgrey);
    g.setFont(text * 0.85f);
    g.drawText("back", labelColumn.withY(back.getY()).withHeight(backCell), juce::Justification::centredLeft);
    for (int i = 0; i < core::kBackMotors; ++i)
        drawMotor({grid.getX() + cell * i + (cell - backCell) * 0.5f, back.getY(), backCell, backCell}, core::kGridMotors + i,
                  motorCount_ > core::kGridMotors + i);

    g.setFont(text * 0.85f);
    g.setColour(juce::Colours::lightgrey);
    g.drawText("left  underside  right", footer.removeFromTop(text * 0.9f).withX(grid.getX()).withWidth(grid.getWidth()),
               juce::Justification::centred);
    if (lastGesture_.isNotEmpty()) {
        g.setColour(juce::Colour(0xff6fd3ff).withAlpha(static_cast<float>(0.35 + 0.65 * gestureFlash_)));
        g.drawText("gesture: " + lastGesture_, footer, juce::Justification::centredLeft);
    }
}

} // namespace armadillo::plugin
