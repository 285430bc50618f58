#pragma once
// The web page window (Setup → Web page…, issue 47; docs/ACCESSIBILITY.md "The web page"): serve
// the running instrument as a page any screen reader and any phone can drive — on or off, the
// port (0 = a free one), the address it listens on (empty = this computer only; an address opens
// it to the network, and every request then needs the session's token, which the address shown
// carries), the address to open, as text to copy and as a QR code for a phone's camera, and what
// the server did (commands taken, clients refused). Every control titled, reached with Tab; what
// happens is announced.
#include "Plugin/Controls.h"
#include <juce_gui_basics/juce_gui_basics.h>

namespace armadillo::plugin {

class ArmadilloProcessor;

class WebPanel : public juce::Component, private juce::Timer {
public:
    explicit WebPanel(ArmadilloProcessor& processor);
    ~WebPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;
    juce::ToggleButton& serveToggle() noexcept { return serve_; }
    juce::TextEditor& address() noexcept { return address_; }

private:
    void timerCallback() override;
    void say(const juce::String& text);
    void showAddress(const juce::String& address);

    ArmadilloProcessor& processor_;
    juce::Label heading_, portLabel_, bindLabel_, addressLabel_, qrLabel_, status_;
    juce::TextEditor port_, bind_, address_;
    juce::ToggleButton serve_ {"Serve the web page"};
    juce::TextButton copy_ {"Copy the address"};
    juce::Image qr_;                 // the address as a QR code (empty while off)
    juce::Rectangle<int> qrArea_;
    juce::String shownAddress_, said_;
};

} // namespace armadillo::plugin
