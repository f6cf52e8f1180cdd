// The CT re-sliced at the tracked tip as a grey PNG (window/level as the viewer's slice views),
// for the demo's navigation stage: no rendering, but VTK's image writers, which the demo's logic
// does not map (rpDemoPictures.h).
#include <type_traits>

#include <vtkImageData.h>
#include <vtkImageMapToWindowLevelColors.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include "rpDemoPictures.h"

RP_DEMO_PICTURES_ENTRY bool roboplan_demo_slice(const rp::demo_pictures::Slice& picture, const std::string& path,
                                                std::string& error) {
  if (!picture.Image) {
    error = "picture '" + path + "': no slice to draw";
    return false;
  }
  vtkNew<vtkImageMapToWindowLevelColors> map;
  map->SetInputData(picture.Image);
  map->SetWindow(picture.Window);
  map->SetLevel(picture.Level);
  map->SetOutputFormatToLuminance();
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(map->GetOutputPort());
  writer->SetFileName(path.c_str());
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    error = "picture '" + path + "' not written (disk full or no permission?)";
    return false;
  }
  return true;
}

static_assert(std::is_same_v<decltype(&roboplan_demo_slice), rp::demo_pictures::SliceFunction>);
