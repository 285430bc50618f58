#pragma once
// The mapping editor (docs/PLUGIN.md "Mapping editor"): the running set's mappings as a list, each
// with its live value as a meter and whether its zone/note is on; a preset choice, Load/Save of a
// mapping file (JSON, docs/MAPPING.md), Set forward; for the selected mapping: its source, its
// destination (kind, channel, number, OSC address, scene parameter), its input range, mute, and
// MIDI learn — "Learn range" (move the arm over the range you want, then finish) and "Learn
// destination" (the next CC, pitch bend, pressure, note or program change arriving at the plugin's
// MIDI input). Add and Remove. Curves, zones, smoothing and postures are edited in the file.
//
// Accessibility: every control has a title and a description and is reached with Tab; the list's
// rows read as text ("2: roll, -90 to 90, to pitch bend channel 2, value 0.41"); learn results
// are announced. Threads: message thread only; it never keeps a pointer to the running set (the
// processor replaces it): every read goes through the processor's mapping access.
#include "Mapping/MappingSpec.h"
#include <juce_gui_basics/juce_gui_basics.h>
#include <memory>

namespace armadillo::plugin {

class ArmadilloProcessor;

class MappingPanel : public juce::Component, private juce::Timer, private juce::ListBoxModel {
public:
    explicit MappingPanel(ArmadilloProcessor& processor);
    ~MappingPanel() override;
    void resized() override;
    void paint(juce::Graphics&) override;

    /// One line describing a mapping (list rows, screen readers, tests).
    static juce::String describeMapping(const mapping::MappingSpec& m);

private:
    // juce::ListBoxModel
    int getNumRows() override;
    void paintListBoxItem(int row, juce::Graphics&, int width, int height, bool selected) override;
    void selectedRowsChanged(int lastRowSelected) override;
    juce::String getNameForRow(int row) override;

    void timerCallback() override;
    void refresh();            // the document changed: list and the selected mapping's controls
    void showSelected();       // the selected mapping → controls
    void edit(const std::function<void(mapping::MappingSpec&)>& change);
    void setMessage(const juce::String& text, bool announceIt);
    void addMapping();
    void removeMapping();
    void toggleRangeLearn();
    void toggleDestinationLearn();
    void loadFile();
    void saveFile();
    int selected() const;

    ArmadilloProcessor& processor_;
    mapping::MappingDocument doc_;   // the copy shown (refreshed when the session's changes)
    juce::String shownName_;
    juce::Label heading_, presetLabel_, message_;
    juce::ComboBox preset_;
    juce::TextButton load_ {"Load..."}, save_ {"Save..."}, forward_ {"Set forward"};
    juce::ListBox list_;
    juce::TextButton add_ {"Add"}, remove_ {"Remove"};
    juce::Label sourceLabel_, destLabel_, channelLabel_, numberLabel_, rangeLabel_, addressLabel_;
    juce::ComboBox source_, dest_, param_;
    juce::Slider channel_, number_;
    juce::TextEditor inLo_, inHi_, address_;
    juce::ToggleButton mute_ {"Mute"};
    juce::TextButton learnRange_ {"Learn range"}, learnDest_ {"Learn destination"};
    std::unique_ptr<juce::FileChooser> chooser_;
    bool updating_ = false;          // controls are being set from the document: no edits
    int lastLearnIndex_ = -1;
};

} // namespace armadillo::plugin
