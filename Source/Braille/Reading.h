#pragma once
// A document laid out for the display, and the reading position in it (thesis §4.3).
// The text is a sequence of units: cells (shown in the steps of the chosen DisplayMethod),
// word gaps and message gaps (each one step with its own cue). Reading forward goes through the
// units in order; reading backward takes the units in reverse order but each cell's steps still
// in their own order ("HELLO" read backward is O L L E H, each letter wrist row first, §4.3.2).
#include "Braille/Cells.h"
#include "Braille/Sensations.h"
#include <string>
#include <vector>

namespace armadillo::braille {

enum class UnitKind : std::uint8_t { Cell, WordGap, MessageGap };

struct ReadingUnit {
    UnitKind kind = UnitKind::Cell;
    Dots cell = 0;                  ///< for Cell units
    int message = 0;                ///< index into the document's messages
    int symbol = 0;                 ///< index into that message's symbols
    std::vector<MotorSet> steps;    ///< cellSteps(cell, method); one empty step for gaps
};

/// Units of a whole document. Spaces become word gaps, message ends become message gaps.
std::vector<ReadingUnit> layoutDocument(const BrailleDocument& doc, DisplayMethod method);

/// What one step of reading shows.
enum class StepKind : std::uint8_t {
    Cell,          ///< `motors` (possibly empty: a pause row)
    WordGap,       ///< the word-boundary cue
    MessageGap,    ///< the message-boundary cue (between two messages)
    TextEnd,       ///< tried to read past the last unit (or before the first, backward)
};

struct ReadingStep {
    StepKind kind = StepKind::TextEnd;
    MotorSet motors = 0;
    int unit = -1;                  ///< unit index, −1 for TextEnd
    int step = 0;                   ///< step index inside the unit
    bool firstOfUnit = false;       ///< the first step of a character (row 1 on the Rows method)
};

class ReadingCursor {
public:
    ReadingCursor() = default;
    explicit ReadingCursor(std::vector<ReadingUnit> units) : units_(std::move(units)) {}

    /// One advance. forward = true reads the units in order, false in reverse. After a change
    /// of direction the current unit starts again from its first step, so the character the
    /// reader was on is felt whole before the ones behind it (scrubbing, §4.4.2).
    ReadingStep advance(bool forward);
    /// Back before the first unit, direction forward.
    void rewind() noexcept;

    const std::vector<ReadingUnit>& units() const noexcept { return units_; }
    int unit() const noexcept { return unit_; }      ///< −1 before the start, units().size() past the end
    int step() const noexcept { return step_; }

private:
    ReadingStep stepAt() const;

    std::vector<ReadingUnit> units_;
    int unit_ = -1;
    int step_ = 0;
    bool forward_ = true;
    bool restartUnit_ = false;
};

} // namespace armadillo::braille

#include "Braille/RollReader.h"

namespace armadillo::braille {

/// Active reading (§4.3): the roll reader moving a cursor. One update per control step.
struct ReadEvent {
    RollUpdate roll {};
    bool stepped = false;          ///< the cursor moved; `step` is what to show
    ReadingStep step {};
};

class ActiveReading {
public:
    void setCursor(ReadingCursor* cursor) noexcept { cursor_ = cursor; }
    RollReader& roll() noexcept { return roll_; }
    void reset() noexcept { roll_.reset(); }
    /// t: the caller's clock (s); axis/normal: earth-frame forearm axis and board normal.
    ReadEvent update(double t, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal, bool valid)
    {
        ReadEvent e;
        e.roll = roll_.update(t, axis, normal, valid);
        if (e.roll.advanced && cursor_) {
            e.stepped = true;
            e.step = cursor_->advance(e.roll.posture == ReadingPosture::Forward);
        }
        return e;
    }

private:
    RollReader roll_;
    ReadingCursor* cursor_ = nullptr;
};

} // namespace armadillo::braille
