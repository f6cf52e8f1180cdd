#ifndef vtkRPScene_h
#define vtkRPScene_h
// The scene (vtkMRMLScene of RoboPlan): owns nodes, gives them unique IDs and names, finds them
// by ID, name and class, and announces changes. Belongs to the main thread.
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

class vtkRPNode;

class vtkRPScene : public vtkObject {
 public:
  static vtkRPScene* New();
  vtkTypeMacro(vtkRPScene, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SceneEvent {
    NodeAddedEvent = 66000,      // callData = vtkRPNode*
    NodeAboutToBeRemovedEvent,   // callData = vtkRPNode*
    NodeRemovedEvent,            // callData = vtkRPNode*
    StartBatchProcessEvent,
    EndBatchProcessEvent,
    StartImportEvent,
    EndImportEvent,
    StartCloseEvent,
    EndCloseEvent,
  };

  /// Adds a node: assigns a unique ID (and a unique name when empty or already taken). Returns
  /// the node, or nullptr if it is already in a scene. A singleton whose class and tag are
  /// already in the scene is not added: the existing node takes its content and is returned.
  vtkRPNode* AddNode(vtkRPNode* node);
  /// Removes a node: references to it are cleared in every other node.
  void RemoveNode(vtkRPNode* node);
  /// Removes every node except the singletons (the views' nodes stay, as in Slicer), with
  /// Start/EndCloseEvent.
  void Clear();

  vtkRPNode* GetNodeByID(const std::string& id) const;
  std::vector<vtkRPNode*> GetNodesByName(const std::string& name) const;
  vtkRPNode* GetFirstNodeByName(const std::string& name) const;
  /// The singleton node of a class (or a subclass) with this tag, or nullptr.
  vtkRPNode* GetSingletonNode(const std::string& tag, const char* className) const;
  /// Nodes that are of the class or derive from it (vtkObject::IsA).
  std::vector<vtkRPNode*> GetNodesByClass(const char* className) const;
  int GetNumberOfNodes() const { return static_cast<int>(this->Nodes.size()); }
  vtkRPNode* GetNthNode(int n) const;
  std::vector<vtkRPNode*> GetNodes() const;

  /// Adds nodes created elsewhere (e.g. read from a scene file), renaming IDs that clash and
  /// remapping every reference among the imported nodes. Start/EndImportEvent around it.
  /// An imported singleton updates the scene's node of the same class and tag (references to it
  /// are remapped to that node). Returns old ID → new ID.
  std::map<std::string, std::string> Import(const std::vector<vtkSmartPointer<vtkRPNode>>& nodes);

  /// Batch processing: observers may defer expensive work until EndBatchProcess.
  void StartBatchProcess();
  void EndBatchProcess();
  bool IsBatchProcessing() const { return this->BatchDepth > 0; }
  bool IsImporting() const { return this->Importing; }
  bool IsClosing() const { return this->Closing; }

  /// Class factory for loading scenes. Built-in node classes are registered on construction;
  /// modules register their own node classes in Setup().
  void RegisterNodeClass(vtkRPNode* prototype);
  vtkSmartPointer<vtkRPNode> CreateNodeByClass(const std::string& className) const;
  std::vector<std::string> GetRegisteredNodeClasses() const;

  /// The ID this scene would give a new node of this class (unique).
  std::string GenerateUniqueID(vtkRPNode* node);
  std::string GenerateUniqueName(const std::string& base) const;

 protected:
  vtkRPScene();
  ~vtkRPScene() override;

 private:
  vtkRPScene(const vtkRPScene&) = delete;
  void operator=(const vtkRPScene&) = delete;
  void InsertNode(vtkRPNode* node);

  std::vector<vtkSmartPointer<vtkRPNode>> Nodes;
  std::map<std::string, vtkRPNode*> NodesByID;
  std::map<std::string, int> NextIDNumber;
  std::map<std::string, vtkSmartPointer<vtkRPNode>> Prototypes;
  int BatchDepth = 0;
  bool Importing = false;
  bool Closing = false;
};

#endif
