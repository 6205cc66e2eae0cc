#include "ssVisibleBlocks.h"

#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSet.h"
#include "vtkSmartPointer.h"

namespace ss
{
namespace
{
void Visit(vtkCompositeDataDisplayAttributes* cda, vtkDataObject* data, bool parentVisible,
  const std::function<void(vtkDataSet*)>& f)
{
  if (!data)
  {
    return;
  }
  // a block's own visibility, else its parent's; a hidden block's children
  // may still be shown by their own (ParaView hides the root and shows the
  // selected blocks)
  const bool visible = (cda && cda->HasBlockVisibility(data)) ? cda->GetBlockVisibility(data) : parentVisible;
  if (auto* ds = vtkDataSet::SafeDownCast(data))
  {
    if (visible)
    {
      f(ds);
    }
    return;
  }
  auto* tree = vtkDataObjectTree::SafeDownCast(data);
  if (!tree)
  {
    return;
  }
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(tree->NewTreeIterator());
  it->VisitOnlyLeavesOff();
  it->TraverseSubTreeOff();
  it->SkipEmptyNodesOn();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    Visit(cda, it->GetCurrentDataObject(), visible, f);
  }
}
}

void ForEachVisibleLeaf(vtkMapper* mapper, vtkDataObject* data, const std::function<void(vtkDataSet*)>& f)
{
  auto* composite = vtkCompositePolyDataMapper2::SafeDownCast(mapper);
  Visit(composite ? composite->GetCompositeDataDisplayAttributes() : nullptr, data, true, f);
}
}
