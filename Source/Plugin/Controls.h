#pragma once
// Controls that behave the same for keyboard, screen-reader and mouse users (issue 24):
//  - ChoiceBox: a combo box whose arrow keys open its list instead of stepping the value, so a
//    keyboard user who left focus on "Scene" or "Mode" cannot change the scene (or end a
//    braille training) by pressing an arrow; Return, Space and the arrows open the list, where
//    the arrows move and Return picks. The mouse wheel never changes it.
//  - ValueSlider: a slider that the mouse wheel changes only while it has keyboard focus (or
//    with Ctrl / Alt held); otherwise the wheel scrolls the page the slider sits on.
//  - paintFocusRing: the visible focus outline every focusable control gets (drawn by the
//    editor over its children, so no control can forget it).
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ChoiceBox : public juce::ComboBox {
public:
    using juce::ComboBox::ComboBox;
    bool keyPressed(const juce::KeyPress& key) override
    {
        const int code = key.getKeyCode();
        if (code == juce::KeyPress::upKey || code == juce::KeyPress::downKey || code == juce::KeyPress::leftKey
            || code == juce::KeyPress::rightKey || code == juce::KeyPress::returnKey || code == juce::KeyPress::spaceKey) {
            if (isEnabled()) showPopup();
            return true;
        }
        return juce::ComboBox::keyPressed(key);
    }
    void mouseWheelMove(const juce::MouseEvent& e, const juce::MouseWheelDetails& wheel) override
    {
        juce::Component::mouseWheelMove(e, wheel);   // to the parent: the page scrolls
    }
    /// JUCE 7.0.5's combo box handler gives the selected text as the accessible name, so an empty
    /// box ("no serial ports found") has none and a screen reader never says what the box is
    /// for. This one names it by its title and gives the selection as its value.
    std::unique_ptr<juce::AccessibilityHandler> createAccessibilityHandler() override
    {
        return std::make_unique<Handler>(*this);
    }

private:
    class Value : public juce::AccessibilityTextValueInterface {
    public:
        explicit Value(juce::ComboBox& box) : box_(box) {}
        bool isReadOnly() const override { return true; }
        juce::String getCurrentValueAsString() const override { return box_.getText(); }
        void setValueAsString(const juce::String&) override {}

    private:
        juce::ComboBox& box_;
    };
    class Handler : public juce::AccessibilityHandler {
    public:
        explicit Handler(ChoiceBox& box)
            : juce::AccessibilityHandler(box, juce::AccessibilityRole::comboBox,
                                         juce::AccessibilityActions()
                                             .addAction(juce::AccessibilityActionType::press, [&box] { box.showPopup(); })
                                             .addAction(juce::AccessibilityActionType::showMenu, [&box] { box.showPopup(); }),
                                         Interfaces {std::unique_ptr<juce::AccessibilityValueInterface>(std::make_unique<Value>(box))}),
              box_(box)
        {
        }
        juce::AccessibleState getCurrentState() const override
        {
            auto state = juce::AccessibilityHandler::getCurrentState().withExpandable();
            return box_.isPopupActive() ? state.withExpanded() : state.withCollapsed();
        }
        juce::String getTitle() const override { return box_.getTitle().isNotEmpty() ? box_.getTitle() : box_.getText(); }
        juce::String getHelp() const override { return box_.getTooltip(); }

    private:
        ChoiceBox& box_;
    };
};

class ValueSlider : public juce::Slider {
public:
    using juce::Slider::Slider;
    void mouseWheelMove(const juce::MouseEvent& e, const juce::MouseWheelDetails& wheel) override
    {
        if (hasKeyboardFocus(true) || e.mods.isCtrlDown() || e.mods.isAltDown()) juce::Slider::mouseWheelMove(e, wheel);
        else juce::Component::mouseWheelMove(e, wheel);
    }
};

/// The focus outline: 2 px, bright, around `area` (in the painting component's coordinates).
inline void paintFocusRing(juce::Graphics& g, juce::Rectangle<int> area)
{
    g.setColour(juce::Colour(0xff4fc3ff));
    g.drawRoundedRectangle(area.toFloat().expanded(2.0f), 3.0f, 2.0f);
}

/// A text field bound to a setting that applies on Return or when focus leaves, not per keystroke
/// (each change may rebuild a rig: a tactor output, an MQTT connection).
inline void commitOnEnter(juce::TextEditor& editor, juce::ValueTree settings, const juce::Identifier& id)
{
    auto commit = [&editor, settings, id]() mutable {
        if (settings[id].toString() != editor.getText().trim()) settings.setProperty(id, editor.getText().trim(), nullptr);
    };
    editor.onReturnKey = commit;
    editor.onFocusLost = commit;
}

/// The next row of a panel's form: `height` pixels off the top of `area`, then a `gap`.
inline juce::Rectangle<int> takeRow(juce::Rectangle<int>& area, int height = 28, int gap = 6)
{
    auto row = area.removeFromTop(height);
    area.removeFromTop(gap);
    return row;
}

} // namespace armadillo::plugin
