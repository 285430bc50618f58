// Pure Data's [armadillo] (issue 46): the instrument on its source's clock (live::LiveSession,
// Pd/SessionInstrument.h), presented on a Pd clock (Pd/PdFront.h). Loaded by Pd from
// armadillo.pd_linux (armadillo_setup).
#include "Pd/PdFront.h"
#include "Pd/SessionInstrument.h"

namespace armadillo::pd {
namespace {

// ---- [armadillo] --------------------------------------------------------------------------------

t_class* armadilloClass = nullptr;

struct Armadillo {
    t_object obj;
    SessionInstrument* instrument;
    Front* front;
};

void armadilloTick(Armadillo* x) { x->front->present(); }

void* armadilloNew(t_symbol*, int, t_atom*)
{
    auto* x = reinterpret_cast<Armadillo*>(pd_new(armadilloClass));
    try {
        x->instrument = new SessionInstrument();
        x->front = new Front(*x->instrument, canvas_getdir(canvas_getcurrent())->s_name);
    } catch (const std::exception& e) {
        pd_error(x, "armadillo: %s", e.what());
        return nullptr;
    }
    x->instrument->setCommands(&x->front->commands);
    x->front->out = outlet_new(&x->obj, &s_anything);
    x->front->clock = clock_new(x, method(armadilloTick));
    x->front->lastStatus = clock_getlogicaltime();
    clock_delay(x->front->clock, kPollMs);
    return x;
}

void armadilloFree(Armadillo* x)
{
    if (x->front && x->front->clock) clock_free(x->front->clock);
    delete x->front;        // (the commands refer to the instrument: they go first)
    delete x->instrument;   // the session stops its threads; the motors go all-off
}

void armadilloAnything(Armadillo* x, t_symbol* s, int argc, t_atom* argv) { x->front->message(x, "armadillo", s, argc, argv); }
void armadilloBang(Armadillo* x) { x->front->message(x, "armadillo", gensym("bang"), 0, nullptr); }

} // namespace

void registerArmadillo()
{
    if (zgetfn(&pd_objectmaker, gensym("armadillo")) != nullptr) return;   // registered already: the library loaded under its other name
    armadilloClass = class_new(gensym("armadillo"), newMethod(armadilloNew),
                               method(armadilloFree), sizeof(Armadillo), CLASS_DEFAULT, A_GIMME, 0);
    class_addbang(armadilloClass, method(armadilloBang));
    class_addanything(armadilloClass, method(armadilloAnything));
}

} // namespace armadillo::pd

/// Pd loads armadillo.pd_linux for [armadillo] (or for `[declare -lib armadillo]`): both classes.
extern "C" __attribute__((visibility("default"))) void armadillo_setup(void)
{
    armadillo::pd::registerArmadillo();
    armadillo::pd::registerArmadilloTilde();
}
