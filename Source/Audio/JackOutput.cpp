#include "Audio/JackOutput.h"
#include "Core/Errors.h"
#include <jack/jack.h>
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace armadillo::audio {

namespace {
// libjack prints its own diagnostics ("Cannot connect to server socket…") on stderr; the caller
// reports the failure once, in its own words.
void quietJack(const char*) {}

std::string serverName()
{
    const char* s = std::getenv("JACK_DEFAULT_SERVER");
    return s && *s ? s : "default";
}
} // namespace

struct JackOutput::Client {
    jack_client_t* handle = nullptr;
    ~Client()
    {
        if (handle) jack_client_close(handle);
    }
};

JackOutput::JackOutput(const std::string& clientName, int channels, const std::string& portPrefix) : client_(std::make_unique<Client>())
{
    jack_set_error_function(quietJack);
    jack_set_info_function(quietJack);
    if (channels < 1 || channels > 32) throw core::IoError("JACK: 1..32 output ports, not " + std::to_string(channels));
    jack_status_t status {};
    client_->handle = jack_client_open(clientName.c_str(), JackNoStartServer, &status);
    if (!client_->handle) {
        if (status & JackServerFailed)
            throw core::IoError("JACK server '" + serverName() + "' not running (start jackd, or give an ALSA device to --tactors)");
        throw core::IoError("JACK: cannot open client '" + clientName + "' (status 0x" + std::to_string(static_cast<unsigned>(status)) + ")");
    }
    name_ = jack_get_client_name(client_->handle);
    sampleRate_ = static_cast<double>(jack_get_sample_rate(client_->handle));
    bufferFrames_ = static_cast<int>(jack_get_buffer_size(client_->handle));
    for (int k = 1; k <= channels; ++k) {
        const std::string port = portPrefix + std::to_string(k);
        jack_port_t* p = jack_port_register(client_->handle, port.c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsOutput | JackPortIsTerminal, 0);
        if (!p) throw core::IoError("JACK: cannot register output port '" + port + "'");
        ports_.push_back(p);
    }
    buffers_.assign(ports_.size(), nullptr);
    jack_set_process_callback(client_->handle, [](jack_nframes_t n, void* self) { return process(n, self); }, this);
    jack_on_shutdown(client_->handle, &JackOutput::shutdown, this);
}

JackOutput::~JackOutput() { stop(); }

int JackOutput::process(std::uint32_t frames, void* self)
{
    auto& o = *static_cast<JackOutput*>(self);
    for (std::size_t c = 0; c < o.ports_.size(); ++c) {
        o.buffers_[c] = static_cast<float*>(jack_port_get_buffer(static_cast<jack_port_t*>(o.ports_[c]), frames));
        std::memset(o.buffers_[c], 0, frames * sizeof(float));
    }
    if (o.render_) o.render_(o.buffers_.data(), static_cast<int>(o.buffers_.size()), static_cast<int>(frames));
    o.frames_.fetch_add(frames, std::memory_order_relaxed);
    return 0;
}

void JackOutput::shutdown(void* self) { static_cast<JackOutput*>(self)->failed_.store(true, std::memory_order_release); }

std::string JackOutput::portName(int channel) const
{
    if (channel < 0 || channel >= channels()) return {};
    return jack_port_name(static_cast<jack_port_t*>(ports_[static_cast<std::size_t>(channel)]));
}

std::vector<std::string> JackOutput::inputPorts(const std::string& pattern) const
{
    std::vector<std::string> names;
    if (!client_->handle) return names;
    const char** found = jack_get_ports(client_->handle, pattern.c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsInput);
    if (found) {
        for (const char** p = found; *p; ++p) names.emplace_back(*p);
        jack_free(found);
    }
    if (names.empty()) throw core::IoError("JACK: no audio input port matches '" + pattern + "' (jack_lsp lists them)");
    return names;
}

void JackOutput::start(Render render)
{
    if (active_) return;
    render_ = std::move(render);
    if (jack_activate(client_->handle) != 0) throw core::IoError("JACK: cannot activate client '" + name_ + "'");
    active_ = true;
}

void JackOutput::connect(const std::string& pattern)
{
    const std::vector<std::string> targets = inputPorts(pattern);
    if (targets.size() < ports_.size())
        throw core::IoError("JACK: '" + pattern + "' matches " + std::to_string(targets.size()) + " input ports, the tactor map needs " +
                      std::to_string(ports_.size()));
    for (std::size_t c = 0; c < ports_.size(); ++c) {
        const int r = jack_connect(client_->handle, jack_port_name(static_cast<jack_port_t*>(ports_[c])), targets[c].c_str());
        if (r != 0 && r != EEXIST) throw core::IoError("JACK: cannot connect " + portName(static_cast<int>(c)) + " to " + targets[c]);
    }
}

int JackOutput::playbackLatencyFrames() const
{
    if (ports_.empty() || !client_->handle) return 0;
    jack_latency_range_t range {};
    jack_port_get_latency_range(static_cast<jack_port_t*>(ports_.front()), JackPlaybackLatency, &range);
    return static_cast<int>(range.max);
}

void JackOutput::stop()
{
    if (!client_ || !client_->handle) return;
    if (active_) jack_deactivate(client_->handle);
    active_ = false;
    jack_client_close(client_->handle);
    client_->handle = nullptr;
}

} // namespace armadillo::audio
