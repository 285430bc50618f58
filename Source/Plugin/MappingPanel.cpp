#include "Plugin/MappingPanel.h"
#include "Plugin/Accessibility.h"
#include "Plugin/PluginProcessor.h"
#include <cmath>

namespace armadillo::plugin {

namespace {

using mapping::DestinationKind;

/// The sources the panel offers, in this order (those this build's parser knows).
const juce::StringArray& sourceChoices()
{
    static const juce::StringArray names = [] {
        juce::StringArray out;
        for (const char* n : {"elevation", "azimuth", "roll", "yaw", "pitch", "qw", "qx", "qy", "qz", "speed", "fluxFace",
                              "fluxEdge", "rollTrigger", "punch", "scene.pitch", "scene.fret", "scene.strike", "panel.knob", "panel.level",
                              "panel.selected", "gesture:*",
                              "gesture:roll", "gesture:punch", "gesture:strike", "gesture:fret", "gesture:select",
                              "gesture:other"}) {
            mapping::SourceSpec s;
            if (mapping::parseSourceName(n, s)) out.add(n);
        }
        return out;
    }();
    return names;
}

struct DestChoice {
    DestinationKind kind;
    const char* name;
};
constexpr DestChoice kDestChoices[] {
    {DestinationKind::Cc7, "MIDI CC (7-bit)"},
    {DestinationKind::Cc14, "MIDI CC (14-bit pair)"},
    {DestinationKind::Nrpn, "MIDI NRPN"},
    {DestinationKind::PitchBend, "MIDI pitch bend"},
    {DestinationKind::ChannelPressure, "MIDI channel pressure"},
    {DestinationKind::Notes, "MIDI notes"},
    {DestinationKind::Mpe, "MPE notes"},
    {DestinationKind::ProgramChange, "MIDI program change"},
    {DestinationKind::Osc, "OSC message"},
    {DestinationKind::Macro, "Macro parameter"},
    {DestinationKind::SceneParam, "Scene parameter"},
    {DestinationKind::SetForward, "Set forward"},
};

int destIndex(DestinationKind k)
{
    for (int i = 0; i < static_cast<int>(std::size(kDestChoices)); ++i)
        if (kDestChoices[i].kind == k) return i;
    return 0;
}

bool hasChannel(DestinationKind k)
{
    return k == DestinationKind::Cc7 || k == DestinationKind::Cc14 || k == DestinationKind::Nrpn || k == DestinationKind::PitchBend
           || k == DestinationKind::ChannelPressure || k == DestinationKind::Notes || k == DestinationKind::Mpe
           || k == DestinationKind::ProgramChange;
}

/// The number field's meaning and range for a destination; false when it has none.
bool numberRange(DestinationKind k, int& lo, int& hi, juce::String& what)
{
    switch (k) {
    case DestinationKind::Cc7: lo = 0; hi = 127; what = "controller"; return true;
    case DestinationKind::Cc14: lo = 0; hi = 31; what = "controller (MSB; LSB is +32)"; return true;
    case DestinationKind::Nrpn: lo = 0; hi = 16383; what = "NRPN parameter"; return true;
    case DestinationKind::Notes: lo = 0; hi = 127; what = "note (event sources)"; return true;
    case DestinationKind::ProgramChange: lo = 0; hi = 127; what = "program"; return true;
    case DestinationKind::Macro: lo = 1; hi = 8; what = "macro"; return true;
    default: return false;
    }
}

juce::String destinationText(const mapping::DestinationSpec& d)
{
    const juce::String ch = " channel " + juce::String(d.channel);
    switch (d.kind) {
    case DestinationKind::Cc7: return "CC " + juce::String(d.number) + ch;
    case DestinationKind::Cc14: return "CC " + juce::String(d.number) + "/" + juce::String(d.number + 32) + ch + (d.lsbFirst ? ", LSB first" : "");
    case DestinationKind::Nrpn: return "NRPN " + juce::String(d.number) + ch;
    case DestinationKind::PitchBend: return "pitch bend" + ch;
    case DestinationKind::ChannelPressure: return "channel pressure" + ch;
    case DestinationKind::Notes: return "notes" + ch;
    case DestinationKind::Mpe: return "MPE notes, master channel " + juce::String(d.channel);
    case DestinationKind::ProgramChange: return "program change" + ch;
    case DestinationKind::Osc:
        return "OSC " + juce::String(d.address)
               + (d.host.empty() && d.port == 0 ? juce::String() : " to " + juce::String(d.host.empty() ? "default host" : d.host) + ":" + juce::String(d.port));
    case DestinationKind::Macro: return "macro " + juce::String(d.number);
    case DestinationKind::SceneParam: return "scene parameter " + juce::String(d.paramId);
    case DestinationKind::SetForward: return "set forward";
    case DestinationKind::Mqtt: return "MQTT " + juce::String(d.address) + " (sent while Setup, MQTT messages is connected)";
    case DestinationKind::Stage:
        return d.stage == core::StageCommand::Kind::CueGoto ? "stage: cue " + juce::String(d.number) : "stage: " + juce::String(mapping::stageActionName(d.stage));
    }
    return {};
}

} // namespace

juce::String MappingPanel::describeMapping(const mapping::MappingSpec& m)
{
    juce::String s = juce::String(mapping::sourceName(m.source));
    if (m.transform.hasIn) s << ", " << juce::String(m.transform.inLo, 1) << " to " << juce::String(m.transform.inHi, 1);
    if (! m.zones.empty()) s << ", " << static_cast<int>(m.zones.size()) << " zones";
    s << ", to " << destinationText(m.to);
    if (! m.label.empty() && m.label != mapping::sourceName(m.source)) s = juce::String(m.label) + ": " + s;
    if (m.muted) s << " (muted)";
    return s;
}

MappingPanel::MappingPanel(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Mapping editor");
    setDescription("Which arm features go to which MIDI, OSC, macro or scene parameter, with live meters and MIDI learn.");
    heading_.setText("Mapping", juce::dontSendNotification);
    heading_.setFont(juce::Font(17.0f, juce::Font::bold));
    addAndMakeVisible(heading_);

    presetLabel_.setText("Preset", juce::dontSendNotification);
    presetLabel_.attachToComponent(&preset_, true);
    describe(preset_, "Mapping preset", "Replace the mapping set with a built-in or user preset (classic, scenerotator, mpe, ...).");
    preset_.onChange = [this] {
        if (updating_ || preset_.getSelectedId() <= 0) return;
        const auto name = preset_.getText();
        const juce::String why = processor_.mapping()->usePreset(name.toStdString());
        setMessage(why.isEmpty() ? "Preset " + name + " loaded." : why, true);
        refresh();
    };
    describe(load_, "Load mapping file", "Load a mapping file (JSON). Errors name the line and column.");
    load_.onClick = [this] { loadFile(); };
    describe(save_, "Save mapping file", "Save the current mapping set as a JSON file to share or edit.");
    save_.onClick = [this] { saveFile(); };
    describe(forward_, "Set forward", "The arm's current azimuth becomes forward for mappings relative to forward (yaw).");
    forward_.onClick = [this] {
        processor_.mapping()->setForward();
        setMessage("Forward set to where the arm points now.", true);
    };

    describe(list_, "Mappings", "Every mapping with its live value. Select one to edit it; the meter shows its output.");
    list_.setModel(this);
    list_.setRowHeight(26);
    list_.setColour(juce::ListBox::backgroundColourId, juce::Colour(0xff141b23));

    describe(add_, "Add mapping", "Add a mapping (elevation to a CC) after the selected one.");
    add_.onClick = [this] { addMapping(); };
    describe(remove_, "Remove mapping", "Remove the selected mapping.");
    remove_.onClick = [this] { removeMapping(); };

    sourceLabel_.setText("Source", juce::dontSendNotification);
    sourceLabel_.attachToComponent(&source_, true);
    source_.addItemList(sourceChoices(), 1);
    describe(source_, "Source", "What the selected mapping reads: a pose angle, a quaternion component, a feature, a scene output or a gesture.");
    source_.onChange = [this] {
        mapping::SourceSpec s;
        if (! mapping::parseSourceName(source_.getText().toStdString(), s)) return;
        edit([s](mapping::MappingSpec& m) {
            m.source = s;
            m.transform.hasIn = false;   // the new source's natural range until learned or typed
        });
    };

    destLabel_.setText("Destination", juce::dontSendNotification);
    destLabel_.attachToComponent(&dest_, true);
    for (const auto& c : kDestChoices) dest_.addItem(c.name, dest_.getNumItems() + 1);
    describe(dest_, "Destination", "Where the selected mapping sends: MIDI, OSC, a macro parameter, a scene parameter.");
    dest_.onChange = [this] {
        const int i = dest_.getSelectedItemIndex();
        if (i < 0) return;
        const auto kind = kDestChoices[i].kind;
        edit([kind](mapping::MappingSpec& m) {
            if (m.to.kind == kind) return;
            m.to.kind = kind;
            int lo = 0, hi = 0;
            juce::String what;
            if (numberRange(kind, lo, hi, what)) m.to.number = juce::jlimit(lo, hi, m.to.number);
            if (kind == DestinationKind::Osc && m.to.address.empty()) m.to.address = "/armadillo/map";
            m.transform.hasOut = false;   // the new destination's full range
        });
    };

    channelLabel_.setText("Channel", juce::dontSendNotification);
    channelLabel_.attachToComponent(&channel_, true);
    channel_.setSliderStyle(juce::Slider::IncDecButtons);
    channel_.setRange(1, 16, 1);
    describe(channel_, "MIDI channel", "The MIDI channel 1 to 16 (for MPE the master channel).");
    channel_.onValueChange = [this] {
        const int v = static_cast<int>(channel_.getValue());
        edit([v](mapping::MappingSpec& m) { m.to.channel = v; });
    };
    numberLabel_.setText("Number", juce::dontSendNotification);
    numberLabel_.attachToComponent(&number_, true);
    number_.setSliderStyle(juce::Slider::IncDecButtons);
    number_.setRange(0, 127, 1);
    describe(number_, "Destination number", "The controller, NRPN parameter, note, program or macro number.");
    number_.onValueChange = [this] {
        const int v = static_cast<int>(number_.getValue());
        edit([v](mapping::MappingSpec& m) { m.to.number = v; });
    };
    addressLabel_.setText("Address", juce::dontSendNotification);
    addressLabel_.attachToComponent(&address_, true);
    describe(address_, "OSC address or scene parameter", "The OSC address (starts with /) the value is sent to.");
    address_.onReturnKey = [this] {
        const auto text = address_.getText().trim().toStdString();
        edit([text](mapping::MappingSpec& m) { m.to.address = text; });
    };
    address_.onFocusLost = address_.onReturnKey;
    for (const auto& entry : processor_.sceneTable().scenes)
        for (std::size_t i = 0; i < entry.specs.size(); ++i)
            if (entry.exposed[i]) param_.addItem(juce::String(entry.specs[i].id), param_.getNumItems() + 1);
    describe(param_, "Scene parameter", "The scene parameter the selected mapping plays (0 to 1 over its range).");
    param_.onChange = [this] {
        const auto id = param_.getText().toStdString();
        edit([id](mapping::MappingSpec& m) { m.to.paramId = id; });
    };

    rangeLabel_.setText("In range", juce::dontSendNotification);
    rangeLabel_.attachToComponent(&inLo_, true);
    describe(inLo_, "Input range low", "The source value that gives the destination's lowest output (Return applies).");
    describe(inHi_, "Input range high", "The source value that gives the destination's highest output (Return applies).");
    for (auto* e : {&inLo_, &inHi_}) {
        e->setInputRestrictions(16, "-0123456789.");
        e->onReturnKey = [this] {
            const double lo = inLo_.getText().getDoubleValue(), hi = inHi_.getText().getDoubleValue();
            if (! (hi != lo) || ! std::isfinite(lo) || ! std::isfinite(hi)) {
                setMessage("The input range needs two different numbers.", true);
                return;
            }
            edit([lo, hi](mapping::MappingSpec& m) {
                m.transform.hasIn = true;
                m.transform.inLo = lo;
                m.transform.inHi = hi;
            });
        };
    }
    describe(mute_, "Mute mapping", "A muted mapping sends nothing; its sounding notes end.");
    mute_.onClick = [this] {
        if (updating_ || selected() < 0) return;
        processor_.mapping()->setMuted(selected(), mute_.getToggleState());
        refresh();
    };
    describe(learnRange_, "Learn range",
             "Press, move the arm over the range you want, press again: that becomes the selected mapping's input range.");
    learnRange_.onClick = [this] { toggleRangeLearn(); };
    describe(learnDest_, "Learn destination",
             "Press, then send a CC (or pitch bend, pressure, note, program change) to the plugin's MIDI input: it becomes the destination.");
    learnDest_.onClick = [this] { toggleDestinationLearn(); };
    describe(message_, "Mapping message", "What the last action did, or why it was refused.");
    message_.setColour(juce::Label::textColourId, juce::Colours::lightgrey);

    for (juce::Component* c : std::initializer_list<juce::Component*> {&preset_, &load_, &save_, &forward_, &list_, &add_, &remove_, &source_,
                                                                        &dest_, &channel_, &number_, &address_, &param_, &inLo_, &inHi_,
                                                                        &mute_, &learnRange_, &learnDest_, &message_})
        addAndMakeVisible(*c);
    setFocusContainerType(FocusContainerType::keyboardFocusContainer);

    refresh();
    startTimerHz(20);
}

MappingPanel::~MappingPanel()
{
    auto access = processor_.mapping();
    access->cancelDestinationLearn();
    if (access->rangeLearnIndex() >= 0) access->finishRangeLearn(false);
}

int MappingPanel::selected() const
{
    const int row = list_.getSelectedRow();
    return row >= 0 && row < static_cast<int>(doc_.mappings.size()) ? row : -1;
}

void MappingPanel::refresh()
{
    {
        auto access = processor_.mapping();
        doc_ = access->document();
        shownName_ = access->name();
        updating_ = true;
        preset_.clear(juce::dontSendNotification);
        juce::StringArray presets;
        for (const auto& p : access->presets()) presets.add(juce::String(p));
        preset_.addItemList(presets, 1);
        for (int i = 0; i < preset_.getNumItems(); ++i)
            if (preset_.getItemText(i) == shownName_) preset_.setSelectedItemIndex(i, juce::dontSendNotification);
        if (preset_.getSelectedId() == 0) preset_.setText(shownName_, juce::dontSendNotification);
        updating_ = false;
    }
    list_.updateContent();
    if (list_.getSelectedRow() >= static_cast<int>(doc_.mappings.size()))
        list_.selectRow(static_cast<int>(doc_.mappings.size()) - 1);
    list_.repaint();
    showSelected();
}

void MappingPanel::showSelected()
{
    const int i = selected();
    updating_ = true;
    const bool has = i >= 0;
    for (juce::Component* c : std::initializer_list<juce::Component*> {&remove_, &source_, &dest_, &channel_, &number_, &address_, &param_,
                                                                        &inLo_, &inHi_, &mute_, &learnRange_, &learnDest_})
        c->setEnabled(has);
    if (has) {
        const auto& m = doc_.mappings[static_cast<std::size_t>(i)];
        const auto name = juce::String(mapping::sourceName(m.source));
        const int s = sourceChoices().indexOf(name);
        if (s >= 0) source_.setSelectedItemIndex(s, juce::dontSendNotification);
        else source_.setText(name, juce::dontSendNotification);
        dest_.setSelectedItemIndex(destIndex(m.to.kind), juce::dontSendNotification);
        channel_.setValue(m.to.channel, juce::dontSendNotification);
        channel_.setEnabled(hasChannel(m.to.kind));
        int lo = 0, hi = 0;
        juce::String what;
        const bool numbered = numberRange(m.to.kind, lo, hi, what);
        number_.setEnabled(numbered);
        if (numbered) {
            number_.setRange(lo, hi, 1);
            number_.setValue(m.to.number, juce::dontSendNotification);
            number_.setDescription("The destination's " + what + ".");
        }
        const bool osc = m.to.kind == DestinationKind::Osc;
        const bool param = m.to.kind == DestinationKind::SceneParam;
        address_.setVisible(osc);
        address_.setText(juce::String(m.to.address), juce::dontSendNotification);
        param_.setVisible(param);
        addressLabel_.setText(param ? "Parameter" : "Address", juce::dontSendNotification);
        addressLabel_.attachToComponent(param ? static_cast<juce::Component*>(&param_) : &address_, true);
        if (param) {
            for (int k = 0; k < param_.getNumItems(); ++k)
                if (param_.getItemText(k) == juce::String(m.to.paramId)) param_.setSelectedItemIndex(k, juce::dontSendNotification);
        }
        double inLo = m.transform.inLo, inHi = m.transform.inHi;
        if (! m.transform.hasIn) mapping::defaultInputRange(m.source.kind, inLo, inHi);
        inLo_.setText(juce::String(inLo, 2), juce::dontSendNotification);
        inHi_.setText(juce::String(inHi, 2), juce::dontSendNotification);
        mute_.setToggleState(m.muted, juce::dontSendNotification);
    } else {
        address_.setVisible(false);
        param_.setVisible(false);
    }
    updating_ = false;
}

void MappingPanel::edit(const std::function<void(mapping::MappingSpec&)>& change)
{
    const int i = selected();
    if (updating_ || i < 0) return;
    auto doc = doc_;
    change(doc.mappings[static_cast<std::size_t>(i)]);
    const juce::String why = processor_.mapping()->setDocument(doc, "edited");
    if (why.isNotEmpty()) setMessage(why, true);   // refused: the running set stays
    else setMessage({}, false);
    refresh();
}

void MappingPanel::setMessage(const juce::String& text, bool announceIt)
{
    message_.setText(text, juce::dontSendNotification);
    if (announceIt) announce(processor_, "mapping", text, juce::AccessibilityHandler::AnnouncementPriority::medium);
}

void MappingPanel::addMapping()
{
    auto doc = doc_;
    if (static_cast<int>(doc.mappings.size()) >= mapping::kMaxMappings) {
        setMessage("A set holds at most " + juce::String(mapping::kMaxMappings) + " mappings.", true);
        return;
    }
    mapping::MappingSpec m;
    m.source.kind = mapping::SourceKind::Elevation;
    m.to.kind = DestinationKind::Cc7;
    m.to.channel = 1;
    m.to.number = 20;
    const int at = selected() < 0 ? static_cast<int>(doc.mappings.size()) : selected() + 1;
    doc.mappings.insert(doc.mappings.begin() + at, m);
    const juce::String why = processor_.mapping()->setDocument(doc, "edited");
    setMessage(why.isEmpty() ? "Mapping " + juce::String(at + 1) + " added: elevation to CC 20." : why, true);
    refresh();
    list_.selectRow(at);
}

void MappingPanel::removeMapping()
{
    const int i = selected();
    if (i < 0) return;
    auto doc = doc_;
    doc.mappings.erase(doc.mappings.begin() + i);
    const juce::String why = processor_.mapping()->setDocument(doc, "edited");
    setMessage(why.isEmpty() ? "Mapping " + juce::String(i + 1) + " removed." : why, true);
    refresh();
}

void MappingPanel::toggleRangeLearn()
{
    auto access = processor_.mapping();
    if (access->rangeLearnIndex() >= 0) {
        const auto what = access->finishRangeLearn(true);
        learnRange_.setButtonText("Learn range");
        access.lock.unlock();
        setMessage(what, true);
        refresh();
        return;
    }
    std::string why;
    if (! access->startRangeLearn(selected(), why)) {
        access.lock.unlock();
        setMessage(why, true);
        return;
    }
    lastLearnIndex_ = selected();
    learnRange_.setButtonText("Finish learning");
    access.lock.unlock();
    setMessage("Learning the range: move the arm over the range you want, then press Finish learning.", true);
}

void MappingPanel::toggleDestinationLearn()
{
    auto access = processor_.mapping();
    if (access->destinationLearnIndex() >= 0) {
        access->cancelDestinationLearn();
        access.lock.unlock();
        setMessage("Destination learn cancelled.", true);
        return;
    }
    access->startDestinationLearn(selected());
    access.lock.unlock();
    setMessage("Waiting for a CC, pitch bend, pressure, note or program change at the plugin's MIDI input...", true);
}

void MappingPanel::loadFile()
{
    chooser_ = std::make_unique<juce::FileChooser>("Load a mapping file", juce::File::getSpecialLocation(juce::File::userDocumentsDirectory), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::openMode | juce::FileBrowserComponent::canSelectFiles, [this](const juce::FileChooser& fc) {
        const auto file = fc.getResult();
        if (file == juce::File()) return;
        const juce::String why = processor_.mapping()->loadFile(file.getFullPathName().toStdString());
        setMessage(why.isEmpty() ? "Loaded " + file.getFileName() + "." : why, true);
        refresh();
    });
}

void MappingPanel::saveFile()
{
    chooser_ = std::make_unique<juce::FileChooser>("Save the mapping set as", juce::File::getSpecialLocation(juce::File::userDocumentsDirectory), "*.json");
    chooser_->launchAsync(juce::FileBrowserComponent::saveMode | juce::FileBrowserComponent::canSelectFiles
                              | juce::FileBrowserComponent::warnAboutOverwriting,
                          [this](const juce::FileChooser& fc) {
                              auto file = fc.getResult();
                              if (file == juce::File()) return;
                              if (! file.hasFileExtension("json")) file = file.withFileExtension("json");
                              const juce::String why = processor_.mapping()->saveFile(file.getFullPathName().toStdString());
                              setMessage(why.isEmpty() ? "Saved as " + file.getFileName() + "." : why, true);
                          });
}

// ------------------------------------------------------------------------------------------------
// List

int MappingPanel::getNumRows()
{
    return static_cast<int>(doc_.mappings.size());
}

juce::String MappingPanel::getNameForRow(int row)
{
    if (row < 0 || row >= getNumRows()) return {};
    const float v = processor_.mapping()->meter(row);
    return juce::String(row + 1) + ": " + describeMapping(doc_.mappings[static_cast<std::size_t>(row)])
           + (std::isfinite(v) ? ", value " + juce::String(v, 2) : juce::String(", no value yet"));
}

void MappingPanel::paintListBoxItem(int row, juce::Graphics& g, int width, int height, bool selectedRow)
{
    if (row < 0 || row >= getNumRows()) return;
    const auto& m = doc_.mappings[static_cast<std::size_t>(row)];
    float v = 0.0f;
    bool on = false;
    {
        auto access = processor_.mapping();
        v = access->meter(row);
        on = access->active(row);
    }
    if (selectedRow) g.fillAll(juce::Colour(0xff2b4a6a));
    auto r = juce::Rectangle<int>(0, 0, width, height).reduced(4, 3);
    auto meter = r.removeFromRight(juce::jmin(140, width / 4));
    g.setColour(juce::Colour(0xff0c1015));
    g.fillRect(meter);
    if (std::isfinite(v)) {
        g.setColour(m.muted ? juce::Colours::grey : juce::Colour(0xff4fc3f7));
        g.fillRect(meter.withWidth(juce::roundToInt(juce::jlimit(0.0f, 1.0f, v) * static_cast<float>(meter.getWidth()))));
    }
    g.setColour(on ? juce::Colours::orange : juce::Colour(0xff3a4654));
    g.fillEllipse(r.removeFromRight(height).reduced(6).toFloat());
    g.setColour(m.muted ? juce::Colours::grey : juce::Colours::white);
    g.setFont(14.0f);
    g.drawText(juce::String(row + 1) + ". " + describeMapping(m), r, juce::Justification::centredLeft, true);
}

void MappingPanel::selectedRowsChanged(int)
{
    showSelected();
}

void MappingPanel::timerCallback()
{
    bool changed = false;
    juce::String notice;
    {
        auto access = processor_.mapping();
        notice = access->takeNotice();
        changed = access->name() != shownName_ || access->document().mappings.size() != doc_.mappings.size();
        double lo = 0.0, hi = 0.0;
        if (access->rangeLearnIndex() >= 0 && access->learnedRange(lo, hi))
            message_.setText("Learning: " + juce::String(lo, 1) + " to " + juce::String(hi, 1) + " so far. Press Finish learning to keep it.",
                             juce::dontSendNotification);
        learnDest_.setButtonText(access->destinationLearnIndex() >= 0 ? "Cancel learn" : "Learn destination");
    }
    if (notice.isNotEmpty()) setMessage(notice, true);
    if (changed || notice.isNotEmpty()) refresh();   // learned, or a state or preset loaded elsewhere
    else list_.repaint();      // the meters
}

// ------------------------------------------------------------------------------------------------
// Layout

void MappingPanel::paint(juce::Graphics& g)
{
    paintPanel(g, *this);
}

void MappingPanel::resized()
{
    auto r = getLocalBounds().reduced(8);
    const int row = 26;
    auto top = r.removeFromTop(row);
    heading_.setBounds(top.removeFromLeft(90));
    top.removeFromLeft(50);
    preset_.setBounds(top.removeFromLeft(juce::jmin(200, top.getWidth() / 3)));
    top.removeFromLeft(6);
    load_.setBounds(top.removeFromLeft(70));
    top.removeFromLeft(4);
    save_.setBounds(top.removeFromLeft(70));
    top.removeFromLeft(4);
    forward_.setBounds(top.removeFromLeft(100));
    r.removeFromTop(6);
    auto bottom = r.removeFromBottom(row * 5 + 24);
    list_.setBounds(r);
    bottom.removeFromTop(6);
    auto line = bottom.removeFromTop(row);
    add_.setBounds(line.removeFromLeft(70));
    line.removeFromLeft(4);
    remove_.setBounds(line.removeFromLeft(80));
    line.removeFromLeft(10);
    mute_.setBounds(line.removeFromLeft(80));
    line.removeFromLeft(6);
    learnRange_.setBounds(line.removeFromLeft(130));
    line.removeFromLeft(4);
    learnDest_.setBounds(line.removeFromLeft(150));
    bottom.removeFromTop(4);
    const int labelW = 90;
    line = bottom.removeFromTop(row);
    line.removeFromLeft(labelW);
    source_.setBounds(line.removeFromLeft(juce::jmin(220, line.getWidth() / 2 - labelW)));
    line.removeFromLeft(labelW);
    dest_.setBounds(line.removeFromLeft(juce::jmin(220, line.getWidth())));
    bottom.removeFromTop(4);
    line = bottom.removeFromTop(row);
    line.removeFromLeft(labelW);
    channel_.setBounds(line.removeFromLeft(110));
    line.removeFromLeft(labelW);
    number_.setBounds(line.removeFromLeft(130));
    bottom.removeFromTop(4);
    line = bottom.removeFromTop(row);
    line.removeFromLeft(labelW);
    inLo_.setBounds(line.removeFromLeft(80));
    line.removeFromLeft(6);
    inHi_.setBounds(line.removeFromLeft(80));
    line.removeFromLeft(labelW);
    address_.setBounds(line.removeFromLeft(juce::jmin(240, line.getWidth())));
    param_.setBounds(address_.getBounds());
    message_.setBounds(bottom);
}

} // namespace armadillo::plugin
