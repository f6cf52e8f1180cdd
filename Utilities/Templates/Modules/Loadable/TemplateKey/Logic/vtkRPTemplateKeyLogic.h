#ifndef vtkRPTemplateKeyLogic_h
#define vtkRPTemplateKeyLogic_h
// TemplateKey logic (no Qt, testable headless): what the module does to the scene, called by its
// panel and its CLI command alike. The template's example job: load files through the one loader
// (rp::LoadPath) and count the scene's nodes by class. Main thread only (it owns no thread).
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>

class vtkRPScene;

class vtkRPTemplateKeyLogic : public vtkObject {
 public:
  static vtkRPTemplateKeyLogic* New();
  vtkTypeMacro(vtkRPTemplateKeyLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// Loads each path into the scene. False with `error` (naming the path) at the first that fails;
  /// what loaded before stays.
  bool LoadFiles(const std::vector<std::string>& paths, std::string& error);
  /// Number of nodes of each class in the scene.
  std::map<std::string, int> CountNodesByClass() const;

 protected:
  vtkRPTemplateKeyLogic() = default;
  ~vtkRPTemplateKeyLogic() override = default;

 private:
  vtkRPTemplateKeyLogic(const vtkRPTemplateKeyLogic&) = delete;
  void operator=(const vtkRPTemplateKeyLogic&) = delete;
  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
};

#endif
