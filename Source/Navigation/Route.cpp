#include "Navigation/Route.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <pugixml.hpp>

namespace armadillo::navigation {
namespace {

/// 1-based line of a byte offset into text.
long lineOf(std::string_view text, std::ptrdiff_t offset)
{
    if (offset < 0) return 0;
    const auto end = std::min<std::size_t>(static_cast<std::size_t>(offset), text.size());
    return 1 + static_cast<long>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
}

std::string trim(std::string s)
{
    const auto notSpace = [](unsigned char c) { return !std::isspace(c); };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), notSpace));
    s.erase(std::find_if(s.rbegin(), s.rend(), notSpace).base(), s.end());
    return s;
}

bool parseNumber(const char* s, double& out)
{
    std::string t = trim(s);
    if (t.empty()) return false;
    const char* b = t.data();
    if (*b == '+') ++b;   // XML Schema decimals may carry a plus sign
    const auto r = std::from_chars(b, t.data() + t.size(), out);
    return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(out);
}

/// A point's name: checked for length and control characters (it is shown and spoken).
std::string checkedName(std::string name, const std::string& source, long line)
{
    name = trim(std::move(name));
    if (name.size() > kMaxWaypointName)
        throw core::InputError(source, line, "name", "a waypoint name is at most " + std::to_string(kMaxWaypointName) + " bytes (this one has " +
                                                   std::to_string(name.size()) + ")");
    for (unsigned char c : name)
        if (c < 0x20 || c == 0x7F) throw core::InputError(source, line, "name", "a waypoint name has a control character");
    return name;
}

void checkPosition(const LatLon& p, const std::string& source, long line)
{
    if (!(p.lat >= -90.0 && p.lat <= 90.0)) throw core::InputError(source, line, "lat", "latitude " + std::to_string(p.lat) + " is outside −90…90");
    if (!(p.lon >= -180.0 && p.lon <= 180.0)) throw core::InputError(source, line, "lon", "longitude " + std::to_string(p.lon) + " is outside −180…180");
}

/// What every route must be, whatever its format.
void finish(Route& r)
{
    if (r.points.size() < 2)
        throw core::InputError(r.source, 0, "", "a route needs at least 2 points (the start and a waypoint); this one has " + std::to_string(r.points.size()));
    if (r.points.size() > kMaxRoutePoints)
        throw core::InputError(r.source, 0, "", "a route has at most " + std::to_string(kMaxRoutePoints) + " points; this one has " + std::to_string(r.points.size()));
    for (std::size_t i = 1; i < r.points.size(); ++i) {
        const double d = distanceM(r.points[i - 1].pos, r.points[i].pos);
        if (d < kMinLegM)
            throw core::InputError(r.source, r.points[i].line, "",
                             "point " + std::to_string(i + 1) + " is " + std::to_string(d) + " m from point " + std::to_string(i) +
                                 ": a leg must be at least " + std::to_string(static_cast<int>(kMinLegM)) + " m long (no direction otherwise)");
    }
}

Waypoint gpxPoint(const pugi::xml_node& node, std::string_view text, const std::string& source)
{
    Waypoint w;
    w.line = lineOf(text, node.offset_debug());
    const pugi::xml_attribute lat = node.attribute("lat"), lon = node.attribute("lon");
    if (!lat) throw core::InputError(source, w.line, "lat", std::string("<") + node.name() + "> has no lat attribute");
    if (!lon) throw core::InputError(source, w.line, "lon", std::string("<") + node.name() + "> has no lon attribute");
    if (!parseNumber(lat.value(), w.pos.lat)) throw core::InputError(source, w.line, "lat", std::string("lat=\"") + lat.value() + "\" is not a number");
    if (!parseNumber(lon.value(), w.pos.lon)) throw core::InputError(source, w.line, "lon", std::string("lon=\"") + lon.value() + "\" is not a number");
    checkPosition(w.pos, source, w.line);
    if (const pugi::xml_node name = node.child("name")) w.name = checkedName(name.child_value(), source, lineOf(text, name.offset_debug()));
    return w;
}

} // namespace

double Route::lengthM() const noexcept
{
    double s = 0.0;
    for (std::size_t i = 1; i < points.size(); ++i) s += distanceM(points[i - 1].pos, points[i].pos);
    return s;
}

Route parseGpx(std::string_view text, const std::string& source)
{
    pugi::xml_document doc;
    // No entity expansion beyond XML's own five (pugixml never fetches external entities).
    const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed) throw core::InputError(source, lineOf(text, parsed.offset), "", std::string("not well-formed XML: ") + parsed.description());
    const pugi::xml_node gpx = doc.document_element();
    if (std::strcmp(gpx.name(), "gpx") != 0)
        throw core::InputError(source, lineOf(text, gpx.offset_debug()), "", std::string("not a GPX file: the root element is <") + gpx.name() + ">, not <gpx>");
    if (const pugi::xml_attribute v = gpx.attribute("version")) {
        const std::string version = v.value();
        if (version != "1.1" && version != "1.0")
            throw core::InputError(source, lineOf(text, gpx.offset_debug()), "version", "GPX version \"" + version + "\" (1.1 and 1.0 are read)");
    }
    Route r;
    r.source = source;
    for (const pugi::xml_node rte : gpx.children("rte")) {
        if (!rte.child("rtept")) continue;
        r.name = checkedName(rte.child_value("name"), source, lineOf(text, rte.offset_debug()));
        for (const pugi::xml_node p : rte.children("rtept")) r.points.push_back(gpxPoint(p, text, source));
        finish(r);
        return r;
    }
    for (const pugi::xml_node trk : gpx.children("trk")) {
        bool any = false;
        for (const pugi::xml_node seg : trk.children("trkseg"))
            if (seg.child("trkpt")) any = true;
        if (!any) continue;
        r.name = checkedName(trk.child_value("name"), source, lineOf(text, trk.offset_debug()));
        Waypoint pending;   // the last point seen, kept at the end whatever its distance
        bool havePending = false;
        for (const pugi::xml_node seg : trk.children("trkseg")) {
            for (const pugi::xml_node p : seg.children("trkpt")) {
                Waypoint w = gpxPoint(p, text, source);
                if (r.points.empty() || !w.name.empty() || distanceM(r.points.back().pos, w.pos) >= kTrackThinningM) {
                    if (!r.points.empty() && distanceM(r.points.back().pos, w.pos) < kMinLegM) continue;   // a repeated fix
                    r.points.push_back(std::move(w));
                    havePending = false;
                } else {
                    pending = std::move(w);
                    havePending = true;
                }
            }
        }
        if (havePending && distanceM(r.points.back().pos, pending.pos) >= kMinLegM) r.points.push_back(std::move(pending));
        finish(r);
        return r;
    }
    for (const pugi::xml_node p : gpx.children("wpt")) r.points.push_back(gpxPoint(p, text, source));
    if (r.points.empty())
        throw core::InputError(source, lineOf(text, gpx.offset_debug()), "", "the GPX file has no route (<rte> with <rtept>), no track (<trk> with <trkpt>) and no <wpt>");
    if (const pugi::xml_node meta = gpx.child("metadata")) r.name = checkedName(meta.child_value("name"), source, lineOf(text, meta.offset_debug()));
    finish(r);
    return r;
}

Route parseRouteJson(std::string_view text, const std::string& source)
{
    const armadillo::core::JsonValue root = armadillo::core::parseJson(text, source);
    Route r;
    r.source = source;
    const armadillo::core::JsonValue* list = &root;
    if (root.kind == armadillo::core::JsonValue::Kind::Object) {
        for (const auto& [key, value] : root.object)
            if (key != "name" && key != "waypoints") throw core::InputError(source, value.line, key, "unknown member \"" + key + "\" (a route has \"name\" and \"waypoints\")");
        if (const auto* n = root.find("name")) {
            if (n->kind != armadillo::core::JsonValue::Kind::String) throw core::InputError(source, n->line, "name", "\"name\" must be a string");
            r.name = checkedName(n->string, source, n->line);
        }
        list = root.find("waypoints");
        if (!list) throw core::InputError(source, root.line, "waypoints", "the route object has no \"waypoints\" list");
    }
    if (list->kind != armadillo::core::JsonValue::Kind::Array)
        throw core::InputError(source, list->line, "", std::string("a route is a list of waypoints, not ") + armadillo::core::JsonValue::kindName(list->kind));
    for (const armadillo::core::JsonValue& p : list->array) {
        if (p.kind != armadillo::core::JsonValue::Kind::Object)
            throw core::InputError(source, p.line, "", std::string("a waypoint is an object {\"lat\":…, \"lon\":…, \"name\":…}, not ") + armadillo::core::JsonValue::kindName(p.kind));
        Waypoint w;
        w.line = p.line;
        bool haveLat = false, haveLon = false;
        for (const auto& [key, value] : p.object) {
            if (key == "lat" || key == "lon") {
                if (value.kind != armadillo::core::JsonValue::Kind::Number) throw core::InputError(source, value.line, key, "\"" + key + "\" must be a number (degrees)");
                (key == "lat" ? w.pos.lat : w.pos.lon) = value.number;
                (key == "lat" ? haveLat : haveLon) = true;
            } else if (key == "name") {
                if (value.kind != armadillo::core::JsonValue::Kind::String) throw core::InputError(source, value.line, key, "\"name\" must be a string");
                w.name = checkedName(value.string, source, value.line);
            } else {
                throw core::InputError(source, value.line, key, "unknown member \"" + key + "\" (a waypoint has \"lat\", \"lon\" and \"name\")");
            }
        }
        if (!haveLat) throw core::InputError(source, p.line, "lat", "the waypoint has no \"lat\"");
        if (!haveLon) throw core::InputError(source, p.line, "lon", "the waypoint has no \"lon\"");
        checkPosition(w.pos, source, w.line);
        r.points.push_back(std::move(w));
        if (r.points.size() > kMaxRoutePoints) break;
    }
    finish(r);
    return r;
}

Route readRouteFile(const std::string& path)
{
    const std::string text = core::readWholeFile(path); // IoError naming the path
    auto endsWith = [&](const char* ext) {
        const std::size_t n = std::strlen(ext);
        if (path.size() < n) return false;
        for (std::size_t i = 0; i < n; ++i)
            if (std::tolower(static_cast<unsigned char>(path[path.size() - n + i])) != ext[i]) return false;
        return true;
    };
    if (endsWith(".gpx")) return parseGpx(text, path);
    if (endsWith(".json")) return parseRouteJson(text, path);
    const auto first = std::find_if(text.begin(), text.end(), [](unsigned char c) { return !std::isspace(c); });
    if (first != text.end() && *first == '<') return parseGpx(text, path);
    if (first != text.end() && (*first == '[' || *first == '{')) return parseRouteJson(text, path);
    throw core::InputError(path, 0, "", "not a route: neither GPX (.gpx, starts with '<') nor a JSON waypoint list (.json, starts with '[' or '{')");
}

} // namespace armadillo::navigation
