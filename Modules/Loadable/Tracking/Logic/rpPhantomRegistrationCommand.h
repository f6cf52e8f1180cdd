#pragma once
// `roboplan phantom-registration <recording.igs.mha> --plus-config <PlusDeviceSet_*.xml>`: fCal's
// phantom registration with automatic landmark detection, from a PLUS recording of the stylus
// resting on the phantom's landmarks (rpPlusPhantomRegistration.h). Prints PhantomToReference,
// the detected landmarks, FRE, PLUS's error figure and the predicted TRE; --compare a PLUS result
// file prints the difference; --out writes the configuration with PhantomToReference in its
// CoordinateDefinitions, as fCal saves it.
#include <ostream>
#include <string>
#include <vector>

namespace rp {

/// Exit code: 0 registered (and written), 1 the inputs could not be used or the comparison
/// exceeded its tolerance, 2 bad arguments.
int RunPhantomRegistrationCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

}  // namespace rp
