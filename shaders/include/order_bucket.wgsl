// included by kernels that bind `starts` and `sorted` (read_write)

// Bucket b's items in increasing order, by insertion sort (twin: `kernels::bucket_order`;
// see `bucket_order.wgsl`).
fn order_bucket(b: u32) {
    let first = starts[b];
    let end = starts[b + 1u];
    for (var i = first + 1u; i < end; i++) {
        let x = sorted[i];
        var j = i;
        while (j > first && sorted[j - 1u] > x) {
            sorted[j] = sorted[j - 1u];
            j--;
        }
        sorted[j] = x;
    }
}
