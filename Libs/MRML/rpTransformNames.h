#pragma once
// Names of the scene's transforms, "FromToTo" as in PLUS and SlicerIGT: a tracked tool's pose
// is <Tool>ToTracker (StylusToTracker), relative to a reference <Tool>ToReference. The one
// place the tracker frame's name is spelt; trackers, servers, panels and the demo use these.
#include <string>

namespace rp {

constexpr const char* TrackerFrameName = "Tracker";

/// "A" + "B" → "AToB".
inline std::string TransformName(const std::string& from, const std::string& to) { return from + "To" + to; }

/// True when `name` is a pose in the tracker frame ("...ToTracker").
inline bool IsToolToTrackerName(const std::string& name) {
  const std::string suffix = TransformName("", TrackerFrameName);
  return name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// "Stylus" → "StylusToTracker"; a name that already is a ToolToTracker name is kept.
inline std::string ToolToTrackerName(const std::string& tool) {
  return IsToolToTrackerName(tool) ? tool : TransformName(tool, TrackerFrameName);
}

/// "StylusToTracker" → "Stylus"; any other name is returned as it is.
inline std::string ToolNameOf(const std::string& transform) {
  return IsToolToTrackerName(transform)
             ? transform.substr(0, transform.size() - TransformName("", TrackerFrameName).size())
             : transform;
}

}  // namespace rp
