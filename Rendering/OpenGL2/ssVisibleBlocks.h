#ifndef ssVisibleBlocks_h
#define ssVisibleBlocks_h

#include <functional>

class vtkDataObject;
class vtkDataSet;
class vtkMapper;

namespace ss
{
/// The datasets of `data` that `mapper` draws: `data` itself when it is a
/// dataset; a composite's leaves whose block visibility is on. The block
/// visibility is the composite mapper's display attributes (ParaView's Block
/// Visibility / BlockSelectors): a block's own where it has one, else its
/// parent's, as vtkCompositePolyDataMapper2 draws them. Before stop 51 a hidden
/// block still cast its shadow and set the clipping range.
void ForEachVisibleLeaf(vtkMapper* mapper, vtkDataObject* data, const std::function<void(vtkDataSet*)>& f);
}

#endif
