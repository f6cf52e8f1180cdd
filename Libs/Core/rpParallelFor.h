#ifndef rpParallelFor_h
#define rpParallelFor_h

// vtkSMPTools::For through one functor type. Header only, for the targets that link VTK's
// CommonCore (RoboPlanCore itself links no VTK).
//
// Why: vtkSMPTools::For compiles VTK's three back-ends (sequential, std::thread, TBB) for every
// functor type it is given. A parallel loop inside a function templated on the voxel type made
// that twelve times over (vtkTemplateMacro): 5-6 s of GCC's time per source at -O3, 20 s in the
// sanitized fuzz build. Here the back-ends are compiled once per source for SliceBody; the loop
// body stays a lambda, compiled and optimised as before, reached by one indirect call per slice.

#include <vtkSMPTools.h>
#include <vtkType.h>

namespace rp {

// A callable body(begin, end) seen through a pointer and a plain function: it refers to the
// lambda, which must outlive the call to ParallelFor (a temporary argument does).
class SliceBody {
 public:
  template <typename Body>
  SliceBody(const Body& body)  // implicit: a lambda is passed as is
      : Object(&body), Call([](const void* object, vtkIdType begin, vtkIdType end) {
          (*static_cast<const Body*>(object))(begin, end);
        }) {}
  void operator()(vtkIdType begin, vtkIdType end) const { this->Call(this->Object, begin, end); }

 private:
  const void* Object;
  void (*Call)(const void*, vtkIdType, vtkIdType);
};

// body(begin, end) over slices of [first, last), on VTK's SMP back-end, as vtkSMPTools::For.
inline void ParallelFor(vtkIdType first, vtkIdType last, SliceBody body) { vtkSMPTools::For(first, last, body); }

// The same with slices of `grain` items.
inline void ParallelFor(vtkIdType first, vtkIdType last, vtkIdType grain, SliceBody body) {
  vtkSMPTools::For(first, last, grain, body);
}

}  // namespace rp

#endif
