#include "Mapping/Mapper.h"
#include "Core/Errors.h"

namespace armadillo::mapping {
void MappingOutput::clear() noexcept { midiCount = 0; oscCount = 0; paramCount = 0; macroChanged = 0; dropped = 0; forwardChanged = false; }

struct MappingSet::Impl {
    MappingDocument doc;
    std::vector<OscTarget> targets {OscTarget {}};
    std::vector<std::string> params;
};
MappingSet::MappingSet() : impl_(std::make_unique<Impl>()) {}
MappingSet::~MappingSet() = default;
std::unique_ptr<MappingSet> MappingSet::build(const MappingDocument& doc, const BuildOptions&)
{
    std::unique_ptr<MappingSet> s(new MappingSet());
    s->impl_->doc = doc;
    return s;
}
const MappingDocument& MappingSet::document() const noexcept { return impl_->doc; }
std::size_t MappingSet::size() const noexcept { return impl_->doc.mappings.size(); }
const std::vector<OscTarget>& MappingSet::oscTargets() const noexcept { return impl_->targets; }
const std::vector<std::string>& MappingSet::sceneParamIds() const noexcept { return impl_->params; }
std::uint32_t MappingSet::macrosUsed() const noexcept { return 0; }
void MappingSet::setMuted(std::size_t, bool) noexcept {}
bool MappingSet::muted(std::size_t) const noexcept { return false; }
float MappingSet::meter(std::size_t) const noexcept { return 0.0f; }
bool MappingSet::active(std::size_t) const noexcept { return false; }

struct Mapper::Impl {
    std::unique_ptr<MappingSet> active;
    double forward = 0.0;
};
Mapper::Mapper() : impl_(std::make_unique<Impl>()) {}
Mapper::~Mapper() = default;
bool Mapper::offer(std::unique_ptr<MappingSet>&) noexcept { return false; }
bool Mapper::canOffer() const noexcept { return false; }
void Mapper::collect() noexcept {}
void Mapper::replace(std::unique_ptr<MappingSet> set) noexcept { impl_->active = std::move(set); }
MappingSet* Mapper::newest() noexcept { return impl_->active.get(); }
void Mapper::process(const MappingInput&, MappingOutput&) noexcept {}
void Mapper::flush(double, MappingOutput&) noexcept {}
void Mapper::allNotesOff(double, MappingOutput&) noexcept {}
MappingSet* Mapper::active() noexcept { return impl_->active.get(); }
void Mapper::requestForward() noexcept {}
void Mapper::setForwardAzimuth(double deg) noexcept { impl_->forward = deg; }
double Mapper::forwardAzimuth() const noexcept { return impl_->forward; }

double readSource(const SourceSpec&, const MappingInput&, double) noexcept { return 0.0; }
bool learnDestination(const std::uint8_t*, int, DestinationSpec&) noexcept { return false; }
void RangeLearner::add(double v) noexcept
{
    if (count == 0 || v < lo) lo = v;
    if (count == 0 || v > hi) hi = v;
    ++count;
}
bool RangeLearner::range(double& outLo, double& outHi) const noexcept
{
    if (count < 2 || !(hi > lo)) return false;
    outLo = lo;
    outHi = hi;
    return true;
}
} // namespace armadillo::mapping
