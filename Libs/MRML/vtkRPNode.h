#ifndef vtkRPNode_h
#define vtkRPNode_h
// Base of every scene node (the vtkMRMLNode of RoboPlan): unique ID, name, string attributes,
// references to other nodes by role, and ModifiedEvent batching with StartModify/EndModify.
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>

class vtkRPScene;

class vtkRPNode : public vtkObject {
 public:
  vtkTypeMacro(vtkRPNode, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Node events (ModifiedEvent is vtkCommand::ModifiedEvent).
  enum {
    ReferenceModifiedEvent = 31000,  // a reference role changed; callData = const char* role
    TransformModifiedEvent = 31001,  // the node's to-world transform changed
  };

  /// New node of the same class (used by the scene's class factory when loading).
  virtual vtkRPNode* CreateNodeInstance() = 0;
  /// Short tag used in scene files and generated names, e.g. "Model".
  virtual const char* GetNodeTagName() = 0;

  const std::string& GetID() const { return this->ID; }
  const std::string& GetName() const { return this->Name; }
  void SetName(const std::string& name);

  // ---- string attributes (free-form key/value, saved with the scene)
  void SetAttribute(const std::string& key, const std::string& value);
  void RemoveAttribute(const std::string& key);
  std::string GetAttribute(const std::string& key) const;  // "" when absent
  bool HasAttribute(const std::string& key) const;
  const std::map<std::string, std::string>& GetAttributes() const { return this->Attributes; }

  // ---- references by role (IDs survive import remapping; cleared when the target is removed)
  void SetNodeReferenceID(const std::string& role, const std::string& id);  // "" clears the role
  void AddNodeReferenceID(const std::string& role, const std::string& id);
  void RemoveNodeReferenceIDs(const std::string& role);
  std::string GetNodeReferenceID(const std::string& role, int n = 0) const;
  int GetNumberOfNodeReferences(const std::string& role) const;
  /// Resolves through the scene; nullptr when not in a scene or the target is missing.
  vtkRPNode* GetNodeReference(const std::string& role, int n = 0) const;
  std::vector<std::string> GetReferenceRoles() const;
  bool HasReferenceTo(const std::string& id) const;

  // ---- modification batching: many changes inside Start/EndModify fire one ModifiedEvent
  int StartModify();
  int EndModify(int previousDisableModify);
  void Modified() override;
  bool GetDisableModifiedEvent() const { return this->DisableModified > 0; }

  vtkRPScene* GetScene() const { return this->Scene; }

  // ---- singletons (Slicer's SingletonTag): at most one node per class and tag in a scene, e.g.
  // the slice node of each view. Adding or importing another one updates the existing node
  // instead; closing the scene keeps them.
  const std::string& GetSingletonTag() const { return this->SingletonTag; }
  bool IsSingleton() const { return !this->SingletonTag.empty(); }
  /// Nodes that describe the views rather than the patient (hidden from data lists).
  virtual bool GetHideFromEditors() const { return false; }
  /// Takes over another node's name, properties, attributes and references (one ModifiedEvent).
  void CopyContent(vtkRPNode* source);

  // ---- serialization of the node's own fields (data such as images live in files)
  using PropertyMap = std::map<std::string, std::string>;
  virtual void WriteProperties(PropertyMap& properties) const;
  virtual void ReadProperties(const PropertyMap& properties);

  // ---- called by the scene only
  void SetIDInternal(const std::string& id) { this->ID = id; }
  void SetSceneInternal(vtkRPScene* scene) { this->Scene = scene; }
  /// Replace references to oldID by newID (import remapping).
  void UpdateReferenceID(const std::string& oldID, const std::string& newID);
  /// Drop references to a node leaving the scene.
  void RemoveReferencesTo(const std::string& id);
  /// Re-resolve references after the scene changed (e.g. after loading), re-observing targets.
  virtual void UpdateReferences() {}

 protected:
  vtkRPNode();
  ~vtkRPNode() override;
  /// A role's IDs changed. Subclasses re-observe (e.g. the parent transform).
  virtual void OnNodeReferenceChanged(const std::string& role);
  void SetSingletonTag(const std::string& tag) { this->SingletonTag = tag; }

 private:
  vtkRPNode(const vtkRPNode&) = delete;
  void operator=(const vtkRPNode&) = delete;

  std::string ID, Name, SingletonTag;
  std::map<std::string, std::string> Attributes;
  std::map<std::string, std::vector<std::string>> References;
  vtkRPScene* Scene = nullptr;  // not owned: the scene owns its nodes
  int DisableModified = 0;
  bool ModifiedWhileDisabled = false;
};

#endif
