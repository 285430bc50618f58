#include "Plugin/WebPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include "Web/QrText.h"

namespace armadillo::plugin {

WebPanel::WebPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    auto settings = processor_.settings();
    heading_.setText("The instrument as a web page", juce::dontSendNotification);
    heading_.setFont(juce::Font(15.0f, juce::Font::bold));
    portLabel_.setText("Port", juce::dontSendNotification);
    bindLabel_.setText("Listen on", juce::dontSendNotification);
    addressLabel_.setText("Open", juce::dontSendNotification);
    qrLabel_.setText("For a phone's camera:", juce::dontSendNotification);
    status_.setTitle("Web page status");
    status_.setJustificationType(juce::Justification::topLeft);
    for (auto* l : {&heading_, &portLabel_, &bindLabel_, &addressLabel_, &qrLabel_, &status_}) addAndMakeVisible(*l);

    describe(port_, "Web page port", "The TCP port the page is served on; 0 takes a free one.");
    port_.setInputRestrictions(5, "0123456789");
    port_.setText(juce::String(static_cast<int>(settings[SettingIds::webPort])), false);
    auto commitPort = [this] {
        const int port = port_.getText().trim().getIntValue();
        if (port != static_cast<int>(processor_.settings()[SettingIds::webPort])) processor_.settings().setProperty(SettingIds::webPort, port, nullptr);
    };
    port_.onReturnKey = commitPort;
    port_.onFocusLost = commitPort;
    describe(bind_, "Listen on address",
             "Empty: this computer only. An address of this computer (0.0.0.0 for every network) lets a phone or tablet open it; "
             "every request then needs the session's token, which the address shown carries.");
    bind_.setText(settings[SettingIds::webBind].toString(), false);
    commitOnEnter(bind_, processor_.settings(), SettingIds::webBind);
    describe(address_, "Web page address", "Where to open the page: type it into a browser, or copy it.");
    address_.setReadOnly(true);
    address_.setCaretVisible(true);
    describe(serve_, "Serve the web page",
             "Serve the running instrument as a page: the arm's orientation as text, the scene's parameters, Panic and Resume, the cues and the messages.");
    serve_.onClick = [this] {
        for (auto* e : {&port_, &bind_}) e->onReturnKey();   // what was typed counts
        const auto why = processor_.setWebPage(serve_.getToggleState());
        const auto address = processor_.webAddress();
        say(why.isNotEmpty() ? why : address.isNotEmpty() ? "Serving the web page at " + address : juce::String("The web page is off"));
    };
    describe(copy_, "Copy the address", "Copy the page's address to the clipboard.");
    copy_.onClick = [this] {
        juce::SystemClipboard::copyTextToClipboard(address_.getText());
        say("Address copied");
    };
    for (auto* c : std::initializer_list<juce::Component*> {&serve_, &port_, &bind_, &address_, &copy_}) addAndMakeVisible(*c);
    timerCallback();
    startTimerHz(4);
}

WebPanel::~WebPanel()
{
    stopTimer();
}

void WebPanel::say(const juce::String& text)
{
    said_ = text;
    announce(processor_, "web", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
    timerCallback();
}

void WebPanel::showAddress(const juce::String& address)
{
    if (address == shownAddress_) return;
    shownAddress_ = address;
    address_.setText(address.isEmpty() ? "(off)" : address, false);
    qr_ = {};
    int w = 0;
    // A phone opens it only when it listens on the network (and then the address carries the token).
    const bool network = processor_.settings()[SettingIds::webBind].toString().trim().isNotEmpty();
    const std::vector<bool> dark = address.isEmpty() || ! network ? std::vector<bool> {} : web::qrModules(address.toStdString(), w);
    if (! dark.empty()) {
        constexpr int quiet = 4, scale = 4;   // the standard quiet zone of 4 modules
        qr_ = juce::Image(juce::Image::RGB, (w + 2 * quiet) * scale, (w + 2 * quiet) * scale, true);
        juce::Graphics g(qr_);
        g.fillAll(juce::Colours::white);
        g.setColour(juce::Colours::black);
        for (int y = 0; y < w; ++y)
            for (int x = 0; x < w; ++x)
                if (dark[static_cast<std::size_t>(y * w + x)]) g.fillRect((x + quiet) * scale, (y + quiet) * scale, scale, scale);
    }
    qrLabel_.setVisible(qr_.isValid());
    repaint();
}

void WebPanel::timerCallback()
{
    const bool on = processor_.webAddress().isNotEmpty();
    serve_.setToggleState(on, juce::dontSendNotification);
    copy_.setEnabled(on);
    showAddress(processor_.webAddress());
    juce::String text = on ? (processor_.settings()[SettingIds::webBind].toString().isEmpty()
                                  ? "Status: serving on this computer only (loopback). To open it from a phone, listen on an address of this computer (0.0.0.0: every network)."
                                  : "Status: serving to the network; every request needs the token in the address.")
                           : "Status: off. Nothing listens.";
    if (said_.isNotEmpty()) text << "\n" << said_;
    const auto log = processor_.webLog();
    for (int i = std::max(0, log.size() - 4); i < log.size(); ++i) text << "\n" << log[i];
    status_.setText(text, juce::dontSendNotification);
}

void WebPanel::paint(juce::Graphics& g)
{
    g.fillAll(juce::Colour(0xff16202a));
    if (qr_.isValid() && ! qrArea_.isEmpty()) {
        const int side = std::min(qrArea_.getWidth(), qrArea_.getHeight());
        g.drawImage(qr_, qrArea_.withSizeKeepingCentre(side, side).toFloat(), juce::RectanglePlacement::centred);
    }
}

void WebPanel::resized()
{
    auto area = getLocalBounds().reduced(12);
    heading_.setBounds(area.removeFromTop(24));
    constexpr int labelWidth = 110;
    auto r = takeRow(area);
    serve_.setBounds(r.removeFromLeft(220));
    r = takeRow(area);
    portLabel_.setBounds(r.removeFromLeft(labelWidth));
    port_.setBounds(r.removeFromLeft(90).reduced(0, 2));
    r.removeFromLeft(16);
    bindLabel_.setBounds(r.removeFromLeft(80));
    bind_.setBounds(r.removeFromLeft(200).reduced(0, 2));
    r = takeRow(area);
    addressLabel_.setBounds(r.removeFromLeft(labelWidth));
    copy_.setBounds(r.removeFromRight(150));
    address_.setBounds(r.reduced(0, 2));
    auto lower = area;
    auto qrColumn = lower.removeFromRight(std::min(220, lower.getWidth() / 2));
    qrLabel_.setBounds(qrColumn.removeFromTop(22));
    qrArea_ = qrColumn.reduced(4);
    status_.setBounds(lower);
}

} // namespace armadillo::plugin
