"""The data side of a mission, resolved at compile time (see ir/dataflow.py for the steps).

records.py    the output: DataIR and its records (slots, scripts, ports, data operations)
state.py      the analysis' working records: node instances, slots, writes, node uses
resolve.py    1-2: load the tree onto blackboards as 4.6.2 does, resolve every key to a slot
types.py      3: the kind of every slot
size.py       4: the capacity of every string and queue
operations.py 5: every data operation decided (ir/dataops.py records), scripts typed
"""
