#pragma once
// What every panel of the editor does the same way for screen-reader and keyboard users (our
// braille readers among them): name and describe a control, announce a change, paint the panel.
#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_gui_basics/juce_gui_basics.h>
#include <iostream>

namespace armadillo::plugin {

/// Accessible title and description, and keyboard focus (Tab reaches it).
inline void describe(juce::Component& c, const juce::String& title, const juce::String& description)
{
    c.setTitle(title);
    c.setDescription(description);
    c.setWantsKeyboardFocus(true);
}

/// What the processor implements so that every announcement is also self-voiced and shown on a
/// braille display (ReaderVoice.h; issue 26). Message thread only.
class SpokenAnnouncements {
public:
    virtual void speakAnnouncement(const juce::String& text, bool interrupt) const = 0;

protected:
    ~SpokenAnnouncements() = default;
};

/// Says `text` to screen readers, and through the app's own voice and braille display when on. JUCE 7.0.5 has no Linux accessibility backend (postAnnouncement
/// does nothing there), so the standalone app on Linux also writes it to stderr, where a screen
/// reader following the terminal reads it, as it reads `armadillo play`. `topic` prefixes that
/// line ("training", "calibration").
inline void announce(const juce::AudioProcessor& processor, const char* topic, const juce::String& text,
                     juce::AccessibilityHandler::AnnouncementPriority priority)
{
    if (text.isEmpty()) return;
    juce::AccessibilityHandler::postAnnouncement(text, priority);
    if (const auto* voiced = dynamic_cast<const SpokenAnnouncements*>(&processor))
        voiced->speakAnnouncement(text, priority == juce::AccessibilityHandler::AnnouncementPriority::high);
#if JUCE_LINUX
    if (processor.wrapperType == juce::AudioProcessor::wrapperType_Standalone)
        std::cerr << "ARMadillo " << topic << ": " << text << std::endl;
#else
    juce::ignoreUnused(processor, topic);
#endif
}

/// The rounded background the device, calibration and training panels share.
inline void paintPanel(juce::Graphics& g, const juce::Component& panel)
{
    g.setColour(juce::Colour(0xff1f2a36));
    g.fillRoundedRectangle(panel.getLocalBounds().toFloat(), 4.0f);
}

} // namespace armadillo::plugin
